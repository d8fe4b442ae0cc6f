#pragma once
/// The narrow phase of the contact candidates: each candidate's normal, clearance and lever at the
/// chain's current sphere centres and the tools' capsules, computed once per configuration and
/// read by every reader of the step (docs/contacts.md, "Collision pipeline"). Since the end of a
/// step is where the next one starts, its geometry is also the next step's; the tools' entries
/// are redone after they move (RefreshTools), everything after the owner invalidates it (the chain
/// moved, the list was rebuilt, a grasp let go of its spheres).
#include <array>
#include <vector>

#include "collision/contact_detector.h"
#include "collision/pair_separation.h"
#include "collision/sphere_chain.h"
#include "collision/verlet_list.h"
#include "common/types.h"
#include "mechanics/contact_law.h"
#include "mechanics/grasps.h"
#include "mechanics/model.h"

namespace viscera::mechanics {

class ContactGeometry {
 public:
  /// For `model`'s obstacles and tools, on `chain`'s spheres and `candidates`' list; a tool's
  /// contact with the spheres `grasps` hold is none. @pre all outlive this.
  ContactGeometry(const Model& model, const collision::SphereChain& chain,
                  const collision::VerletList& candidates, const Grasps& grasps);

  /// The tools' capsules (present once a tool had a target), as the broad phase searches them.
  const std::vector<collision::ToolCapsule>& capsules() const { return capsules_; }
  const collision::ToolCapsule& capsule(int index) const { return capsules_[index]; }
  /// Tool `index`'s shaft from its port to `tip`.
  void PlaceTool(int index, const Vec3& tip) {
    const ToolParams& tp = model_.params().tools[index];
    capsules_[index] = {true, tp.port, tip, tp.radius};
  }
  void HideTool(int index) { capsules_[index].present = false; }

  /// The chain, the list or the held spheres changed: Ensure computes everything again.
  void Invalidate() { valid_ = false; }
  /// Every candidate's geometry at the current configuration, unless it is still valid.
  void Ensure();
  /// The tools' entries again, after the tools moved (nothing while invalid).
  void RefreshTools();

  /// Candidate i's geometry (by index in the list). @pre Ensure since the last change.
  const PairGeometry& operator[](size_t i) const { return penalties_[i]; }
  const std::vector<PairGeometry>& penalties() const { return penalties_; }
  /// The deepest self or environment candidate's depth (m).
  double deepest() const { return deepest_; }
  /// A candidate's geometry, held spheres included (whether they are out of the shaft).
  PairGeometry Raw(const collision::ContactCandidate& c) const;

 private:
  // Raw, except that a tool's contact with the part of the tube its jaws hold is no contact
  // (far away).
  PairGeometry Of(const collision::ContactCandidate& c) const;
  // A self pair's penalty from its centres' separation (Raw's and SelfBatch's).
  PairGeometry SelfPenalty(const collision::PairSeparation& separation) const;
  // Raw of `count` (1 to 4) self candidates, by index in the list, into penalties_.
  void SelfBatch(const std::array<int, 4>& batch, int count);

  const Model& model_;
  const collision::SphereChain& chain_;
  const collision::VerletList& candidates_;
  const Grasps& grasps_;
  double radius_;
  // The model's obstacles (immutable), prepared once for the narrow phase's queries.
  std::vector<collision::PreparedObstacle> obstacles_;
  std::vector<collision::ToolCapsule> capsules_;
  std::vector<PairGeometry> penalties_;  // per candidate, valid while valid_
  bool valid_ = false;
  double deepest_ = 0.0;
};

}  // namespace viscera::mechanics
