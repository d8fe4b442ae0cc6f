#pragma once
/// The mutable state of one simulation: plain, copyable, snapshot-able (the MuJoCo mjData
/// habit, minus the scratch, which lives in Workspace).
#include <cstdint>
#include <vector>

#include "mechanics/model.h"

namespace viscera::mechanics {

struct State {
  double t = 0.0;          ///< simulated time (s)
  Points q;                ///< control points (m), #N by 3
  Points qd;               ///< their velocities (m/s), #N by 3
  std::vector<ToolState> tools;  ///< one per model tool: pose, grasp, force feedback
  int64_t steps = 0;       ///< steps taken
  /// Steps whose result was not finite; each one reset the state to the model's start.
  int64_t nonfinite_resets = 0;
};

/// The model's starting pose at rest, t = 0.
inline State InitialState(const Model& model) {
  State s;
  s.q = model.params().initial_q;
  s.qd = Points::Zero(model.num_points(), 3);
  s.tools.resize(model.params().tools.size());
  for (size_t i = 0; i < s.tools.size(); ++i) s.tools[i].tip = model.params().tools[i].port;
  return s;
}

}  // namespace viscera::mechanics
