#pragma once
/// The tools' tips as unknowns of the implicit solve (docs/tool-coupling.md): the virtual coupling
/// to the device's target and the tip's mass give each tip its own rows; the force evaluation adds
/// every tip-tube contact and grasp to them and to the links between a tip and the tube's windows,
/// which the integrator eliminates by a Schur complement. Between the solves of a sub-step, the
/// tip contacts are revised: released where they would pull, stiffened where the law stiffens
/// faster than its linearization foresaw, activated where a pair apart ends in contact.
#include <algorithm>
#include <utility>
#include <vector>

#include "collision/contact_detector.h"
#include "collision/sphere_chain.h"
#include "common/types.h"
#include "mechanics/contact_law.h"
#include "mechanics/contact_window.h"
#include "mechanics/model.h"
#include "mechanics/state.h"

namespace viscera::mechanics {

/// A tip's own rows of the implicit system at the sub-step's start: force on the tip (coupling
/// and tissue, the tissue's by the lever rule), K = -dF/dtip and D = -dF/dv_tip.
struct TipRows {
  bool present = false;  // initialized (a target came): its tip is three unknowns
  double mass = 0.0;
  Vec3 force = Vec3::Zero();
  Mat3 k = Mat3::Zero(), d = Mat3::Zero();
  Vec3 tissue = Vec3::Zero();  // what the tool puts on the tube (ToolState::tissue_force)
};
/// One contact's or grasp's coupling between a tip and a sphere's window: the window's force
/// changes by -w_i (k dx_tip + d dv_tip) at its point first + i (K's and D's off-diagonal blocks;
/// the tip's by the window's motion are their transposes).
struct TipLink : ContactWindow {
  int tool = 0;
  Mat3 k = Mat3::Zero(), d = Mat3::Zero();
};

class TipCoupling {
 public:
  /// @pre model, chain and law outlive this.
  TipCoupling(const Model& model, const collision::SphereChain& chain, const ContactLaw& law);

  /// Tool `index`'s target path across this sub-step.
  void SetPath(int index, const Vec3& from, const Vec3& to) {
    from_[index] = from;
    to_[index] = to;
  }
  /// The coupling's rows, the tips where state.tools has them and the target at `fraction`
  /// (0..1) of the path; the force evaluations start from them.
  void Place(const State& state, double fraction);

  /// A force evaluation starts: the coupling's rows, no link or pair yet.
  void StartForces() {
    links_.clear();
    pairs_.clear();
    rows_ = coupling_rows_;  // same size: no allocation
  }
  /// A tool contact released as pulling (candidate index): it does not act.
  bool Released(int candidate) const {
    return !released_.empty() &&
           std::find(released_.begin(), released_.end(), candidate) != released_.end();
  }
  /// A tool pair apart at the sub-step's start that the last solve ended in contact: it acts.
  bool Activated(int candidate) const {
    return !activated_.empty() &&
           std::find(activated_.begin(), activated_.end(), candidate) != activated_.end();
  }
  /// The slope a tool pair is solved with: its law's, or the stiffer one a revision found.
  double Slope(int candidate, double slope) const {
    for (const auto& [stiffened, s] : stiffened_) {
      if (stiffened == candidate) slope = std::max(slope, s);
    }
    return slope;
  }
  /// Tool `tool`'s contact pushes the tube with `force` at `lever` on the shaft: its tip is
  /// pushed back, moved there by the lever rule (the shaft pivots at the port, which takes the
  /// rest across the shaft).
  void AddContactForce(int tool, const ShaftLever& lever, const Vec3& force) {
    rows_[tool].force -= lever.Apply(force);
    rows_[tool].tissue += force;
  }
  /// The same contact's stiffness kn and damping dn (candidate `candidate` with `sphere`, p its
  /// penalty and law its law at the start) in the tip's rows and a link to the sphere's window.
  void AddContactCoupling(int candidate, int tool, int sphere, const ContactPenalty& p,
                          const ContactLaw::Law& law, const Mat3& kn, const Mat3& dn);
  /// Tool `tool`'s grasp pulls the tube with `force`: the jaws are pulled back.
  void AddGraspForce(int tool, const Vec3& force) {
    rows_[tool].force -= force;
    rows_[tool].tissue += force;
  }
  /// The grasp's stiffness k in the tip's rows and a link to the window `at`.
  void AddGraspCoupling(int tool, const ContactWindow& at, double k) {
    rows_[tool].k += k * Mat3::Identity();
    links_.push_back({at, tool, -k * Mat3::Identity(), Mat3::Zero()});
  }
  const std::vector<TipRows>& rows() const { return rows_; }
  const std::vector<TipLink>& links() const { return links_; }

  /// After a solve whose end velocities are v + dv (the tube: #N by 3, dv's 3N values) and tip_v
  /// (3 per tool), on the candidates `list` and their `geometry`: releases the tool contacts whose
  /// linearized force at the sub-step's end would pull, stiffens those whose law at the predicted
  /// end depth pushes more than 5 % beyond their linearization, and activates pairs apart that
  /// end in contact. Says whether any changed, so that the solve is done again.
  bool Revise(double h, const Points& v, const double* dv, const VecX& tip_v,
              const std::vector<collision::ContactCandidate>& list,
              const std::vector<PairGeometry>& geometry);
  /// A sub-step starts with every contact as its start's law has it.
  void ClearRevisions() {
    released_.clear();
    stiffened_.clear();
    activated_.clear();
  }

  /// After the solve moved tool `index`'s tip by h from `start_velocity`: the force the solve's
  /// coupling applied, as the hand feels it.
  Vec3 OnHand(int index, double h, const Vec3& start_velocity, const ToolState& ts) const;
  /// Whether tool `index`'s coupling was at the device's maximum in this sub-step.
  bool saturated(int index) const { return coupling_saturated_[index]; }

 private:
  ContactWindow Window(int sphere) const { return ContactWindow::Of(chain_.spheres()[sphere]); }

  const Model& model_;
  const collision::SphereChain& chain_;
  const ContactLaw& law_;
  // Each tool's target path across this sub-step, the coupling's part of its rows (Place; the
  // force evaluation adds the tissue's), and its links.
  std::vector<Vec3> from_, to_;
  std::vector<TipRows> coupling_rows_, rows_;
  std::vector<char> coupling_saturated_;
  std::vector<TipLink> links_;
  // The tool contacts of the last force evaluation (their law at the sub-step's start), and
  // those released as pulling (candidate indices).
  struct Pair {
    int candidate = 0, tool = 0, sphere = 0;
    ShaftLever lever;
    double depth = 0.0, force = 0.0, slope = 0.0;  // slope: as linearized
    Vec3 normal = Vec3::Zero();
  };
  std::vector<Pair> pairs_;
  std::vector<int> released_;
  // Tool pairs solved again with a stiffer slope (candidate, slope): the law's at the depth the
  // last solve predicted for the sub-step's end, where it stiffens faster than its start's slope
  // foresaw.
  std::vector<std::pair<int, double>> stiffened_;
  // Tool pairs apart at the sub-step's start (and not closing fast enough to act) that the last
  // solve ended in contact: solved again with them acting (candidate indices).
  std::vector<int> activated_;
};

}  // namespace viscera::mechanics
