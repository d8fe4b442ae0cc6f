#pragma once
/// What each tool's hand feels at the end of a step (ToolState::force, torque, clamped, stiffness):
/// the virtual coupling's reaction, clamped to the device's maximum, its torque about the port,
/// and the local stiffness a 1 kHz device loop renders between server steps (docs/haptics.md).
/// With the tips in the implicit solve the force is the mean of the impulse the solve's coupling
/// applied over the step, which the sub-steps add to (AddImpulse).
#include <vector>

#include "collision/contact_detector.h"
#include "common/types.h"
#include "mechanics/contact_law.h"
#include "mechanics/grasps.h"
#include "mechanics/model.h"
#include "mechanics/state.h"

namespace viscera::mechanics {

class HapticOutput {
 public:
  /// For `model`'s tools; `tips_in_solve`: the implicit solve moves the tips (Interactions).
  HapticOutput(const Model& model, bool tips_in_solve);

  /// A step starts: no impulse on any hand yet (a blown-up step's NaN stays in it).
  void StartStep();
  /// Tool `index`'s coupling put `on_hand` on the hand over a sub-step of length h; `saturated`:
  /// at the device's maximum.
  void AddImpulse(int index, double h, const Vec3& on_hand, bool saturated) {
    impulse_[index] += h * on_hand;
    time_[index] += h;
    if (saturated) saturated_[index] = 1;
  }

  /// After the step, for each tool that has had a target: the force, clamp and torque, and the
  /// stiffness of each touching tool contact of `list` (with `geometry`, its narrow phase at the
  /// step's end, and `law`) and of the grasp, each in series with the coupling.
  void EndStep(const std::vector<collision::ContactCandidate>& list,
               const std::vector<PairGeometry>& geometry, const ContactLaw& law,
               const Grasps& grasps, State* state) const;

 private:
  const Model& model_;
  bool tips_in_solve_;
  std::vector<Vec3> impulse_;
  std::vector<double> time_;
  std::vector<char> saturated_;  // the coupling saturated in one of the step's sub-steps
};

}  // namespace viscera::mechanics
