#pragma once
/// force_feedback_t from a mechanics state: one function for the live session, which
/// publishes it, and for replay, which checks every recorded one against it bit for bit.
#include <cstdint>
#include <string>

#include <viscera_proto/force_feedback_t.hpp>

#include "mechanics/state.h"
#include "mechanics/tool.h"

namespace viscera::session {

/// Fills every field of `msg` the mechanics decide (step, time, force, torque, tip,
/// stiffness, clamped, grasping) for tool `tool` of `state`, plus `active` from its target
/// and `pose_seq`. Leaves header and pose_utime (the client's own clock) to the caller.
/// @pre tool < state.tools.size()
void FillForceFeedback(const mechanics::State& state, size_t tool,
                       const mechanics::ToolTarget& target, int64_t pose_seq,
                       viscera_proto::force_feedback_t* msg);

/// "" when the fields FillForceFeedback writes are bit for bit the same in `a` and `b`,
/// else the first that differs, with both values.
std::string ForceFeedbackDifference(const viscera_proto::force_feedback_t& a,
                                    const viscera_proto::force_feedback_t& b);

}  // namespace viscera::session
