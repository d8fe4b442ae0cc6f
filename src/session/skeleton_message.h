#pragma once
/// SkeletonMessage: the skeleton_state_t a session publishes, filled from the mechanics
/// state (mechanics thread only): the control points, and the collision spheres spread by
/// arc length along the curve.
#include <cstdint>

#include <viscera_proto/skeleton_state_t.hpp>

#include "mechanics/model.h"
#include "mechanics/state.h"
#include "spline/arc_length.h"

namespace viscera::session {

class SkeletonMessage {
 public:
  explicit SkeletonMessage(int64_t session_id) : session_id_(session_id) {}

  /// The message of `state` with the next sequence number; valid until the next call.
  const viscera_proto::skeleton_state_t& Fill(const mechanics::Model& model,
                                              const mechanics::State& state);

 private:
  int64_t session_id_;
  int64_t seq_ = 0;
  viscera_proto::skeleton_state_t message_;  // kept: its arrays are reused from call to call
  spline::ArcLengthTable arc_table_;
};

}  // namespace viscera::session
