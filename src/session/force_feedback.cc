#include "session/force_feedback.h"

#include <bit>

#include "common/check.h"

namespace viscera::session {

void FillForceFeedback(const mechanics::State& state, size_t tool,
                       const mechanics::ToolTarget& target, int64_t pose_seq,
                       viscera_proto::force_feedback_t* msg) {
  const mechanics::ToolState& t = state.tools[tool];
  msg->tool = static_cast<int32_t>(tool);
  msg->step = state.steps;
  msg->sim_time = state.t;
  for (int a = 0; a < 3; ++a) {
    msg->force[a] = t.force(a);
    msg->torque[a] = t.torque(a);
    msg->tip[a] = t.tip(a);
    for (int b = 0; b < 3; ++b) msg->stiffness[a][b] = t.stiffness(a, b);
  }
  msg->pose_seq = pose_seq;
  msg->clamped = t.clamped;
  msg->active = target.active;
  msg->grasping = t.grasping;
}

namespace {

// Bitwise, so that -0.0 vs 0.0 and NaN payloads count as differences too.
bool SameBits(double a, double b) {
  return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b);
}

}  // namespace

std::string ForceFeedbackDifference(const viscera_proto::force_feedback_t& a,
                                    const viscera_proto::force_feedback_t& b) {
  if (a.tool != b.tool) return Cat("tool ", a.tool, " vs ", b.tool);
  if (a.step != b.step) return Cat("step ", a.step, " vs ", b.step);
  if (!SameBits(a.sim_time, b.sim_time)) return Cat("sim_time ", a.sim_time, " vs ", b.sim_time);
  for (int i = 0; i < 3; ++i) {
    if (!SameBits(a.force[i], b.force[i]))
      return Cat("force[", i, "] ", a.force[i], " vs ", b.force[i]);
    if (!SameBits(a.torque[i], b.torque[i]))
      return Cat("torque[", i, "] ", a.torque[i], " vs ", b.torque[i]);
    if (!SameBits(a.tip[i], b.tip[i])) return Cat("tip[", i, "] ", a.tip[i], " vs ", b.tip[i]);
    for (int j = 0; j < 3; ++j) {
      if (!SameBits(a.stiffness[i][j], b.stiffness[i][j])) {
        return Cat("stiffness[", i, "][", j, "] ", a.stiffness[i][j], " vs ", b.stiffness[i][j]);
      }
    }
  }
  if (a.pose_seq != b.pose_seq) return Cat("pose_seq ", a.pose_seq, " vs ", b.pose_seq);
  if (a.clamped != b.clamped) return Cat("clamped ", int{a.clamped}, " vs ", int{b.clamped});
  if (a.active != b.active) return Cat("active ", int{a.active}, " vs ", int{b.active});
  if (a.grasping != b.grasping) return Cat("grasping ", int{a.grasping}, " vs ", int{b.grasping});
  return "";
}

}  // namespace viscera::session
