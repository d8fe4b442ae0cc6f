#pragma once
/// Everything that touches the intestine from outside its own elasticity, for one simulation:
/// the sphere chain and its contacts (self, environment, tools: penalty springs with damping and
/// regularized Coulomb friction, France et al. 2005 section 3.5), the laparoscopic tools with
/// their virtual coupling and grasps, and the haptic output. Owned by the stepping thread's
/// Workspace; allocates nothing in steady state.
#include <span>
#include <vector>

#include "collision/contact_detector.h"
#include "collision/sphere_chain.h"
#include "collision/verlet_list.h"
#include "mechanics/block_band.h"
#include "mechanics/model.h"
#include "mechanics/state.h"

namespace viscera::mechanics {

class Interactions {
 public:
  explicit Interactions(const Model& model);

  /// Whether a model needs this at all (self-contacts, obstacles or tools).
  static bool Needed(const Model& model);

  /// Sub-steps this step needs so that no pair closes in by more than a fifth of the radius per
  /// sub-step (an impact found a sub-step late would start its penalty spring compressed,
  /// creating energy): at least the model's, at most kMaxSubsteps.
  int RequiredSubsteps(const State& state);
  static constexpr int kMaxSubsteps = 32;

  /// At the start of a sub-step: takes new targets (empty: keep the last), advances the tools
  /// toward them (implicitly, against their contact and grasp reactions at the current pose),
  /// opens or closes grasps, re-places the spheres and finds the contact candidates.
  void BeginSubstep(std::span<const ToolTarget> targets, double h, State* state);

  /// Adds contact and grasp forces at (q, qd) to F (#N by 3), with the tools where
  /// BeginSubstep left them; returns their energy (J). K, D as in ForceJacobians: each contact's
  /// stiffness enters the blocks of its own sphere's window (a self pair is linearized with the
  /// other sphere held), so the system keeps the chain's band.
  double AddForces(const Points& q, const Points& qd, Points* F, BlockBand* K, BlockBand* D);

  /// After the step: contact counts and clearance, tool force feedback (clamped), stiffness.
  void EndStep(State* state);

  const collision::SphereChain& chain() const { return chain_; }
  /// Every pair that may touch within the sub-step, and some farther (a Verlet list).
  const std::vector<collision::ContactCandidate>& candidates() const { return candidates_.candidates(); }
  /// Broad-phase searches so far (the list is reused between them).
  int64_t searches() const { return candidates_.searches(); }

 private:
  struct Penalty {
    bool active = false;
    Vec3 force = Vec3::Zero();  // on the sphere
    Vec3 normal = Vec3::Zero();
    double depth = 0.0;         // penetration (m), > 0 when active
    double clearance = 0.0;     // signed distance beyond contact (m)
    double lever = 1.0;         // tool contacts: fraction along the shaft from the port
  };
  // Narrow phase of one candidate at the current sphere centres: normal, clearance, lever.
  Penalty Geometry(const collision::ContactCandidate& c) const;
  // Velocity of the candidate's other side at the contact (zero for obstacles), from the
  // velocities last gathered.
  Vec3 OtherVelocity(const collision::ContactCandidate& c, double lever) const;
  // Geometry plus the force law, at the velocities last gathered by GatherVelocities.
  Penalty Evaluate(const collision::ContactCandidate& c) const;
  Vec3 SphereVelocity(int sphere, const Points& qd) const;
  void GatherVelocities(const Points& qd);
  // Contact margin plus twice the fastest travel in h, from the gathered sphere velocities.
  double CandidateMargin(const State& state, double h) const;
  void AddToWindow(int sphere, const Vec3& f, Points* F) const;
  void AddWindowOuter(int first, const std::array<double, 4>& w, const Mat3& h, BlockBand* m) const;
  void AdvanceTool(int index, double h, const Points& q, const Points& qd, ToolState* ts);
  void UpdateGrasp(int index, double h, bool active, ToolState* ts);
  // The grasp spring's stretch: jaws - tube - offset.
  Vec3 GraspStretch(int index, const Points& q) const;

  const Model& model_;
  double radius_, margin_;
  // The implicit integrator's sub-step: pairs predicted to touch within it act already
  // (speculative contacts); 0 for RK4, which evaluates the true penetration at every stage.
  double speculative_h_ = 0.0;
  // RequiredSubsteps left candidates for the whole step: the first sub-step reuses them.
  bool candidates_fresh_ = false;

  collision::SphereChain chain_;
  collision::VerletList candidates_;
  std::vector<collision::ToolCapsule> capsules_;
  std::vector<Vec3> tool_velocity_;
  std::vector<bool> grasping_;
  std::vector<CurvePoint> grasp_at_;
  // A grasp engages at the jaws' current offset from the tube, which then shrinks (the tube is
  // drawn into the jaws), and fades out on release: the force never jumps.
  std::vector<Vec3> grasp_offset_;
  std::vector<double> grasp_scale_;
  // Per force evaluation: sphere velocities, and each sphere's summed contact stiffness and
  // damping (spread onto its window once, not once per contact).
  std::vector<Vec3> sphere_velocity_;
  std::vector<Mat3> sphere_k_, sphere_d_;
  std::vector<char> sphere_touched_;
};

}  // namespace viscera::mechanics
