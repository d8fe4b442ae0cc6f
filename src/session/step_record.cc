#include "session/step_record.h"

#include <cmath>

namespace viscera::session {

void FillStepRecord(int8_t kind, int64_t step, std::span<const mechanics::ToolTarget> targets,
                    std::span<const PoseInput> poses, viscera_proto::step_record_t* record) {
  record->kind = kind;
  record->step = step;
  record->num_tools = static_cast<int32_t>(targets.size());
  record->tools.resize(targets.size());
  for (size_t i = 0; i < targets.size(); ++i) {
    const mechanics::ToolTarget& t = targets[i];
    viscera_proto::tool_target_t& r = record->tools[i];
    for (int a = 0; a < 3; ++a) r.tip[a] = t.tip(a);
    r.orientation[0] = t.orientation.w();
    r.orientation[1] = t.orientation.x();
    r.orientation[2] = t.orientation.y();
    r.orientation[3] = t.orientation.z();
    r.jaw = t.jaw;
    r.active = t.active;
    r.pose_seq = i < poses.size() ? poses[i].seq : -1;
  }
}

bool TargetsOf(const viscera_proto::step_record_t& record,
               std::vector<mechanics::ToolTarget>* targets) {
  if (record.num_tools < 0 || static_cast<size_t>(record.num_tools) != record.tools.size()) {
    return false;
  }
  targets->resize(record.tools.size());
  for (size_t i = 0; i < record.tools.size(); ++i) {
    const viscera_proto::tool_target_t& r = record.tools[i];
    mechanics::ToolTarget& t = (*targets)[i];
    t.tip = Vec3(r.tip[0], r.tip[1], r.tip[2]);
    // the exact quaternion the session used: no renormalisation here
    t.orientation =
        Eigen::Quaterniond(r.orientation[0], r.orientation[1], r.orientation[2], r.orientation[3]);
    t.jaw = r.jaw;
    t.active = r.active;
    if (!t.tip.allFinite() || !t.orientation.coeffs().allFinite() || !std::isfinite(t.jaw)) {
      return false;
    }
  }
  return true;
}

}  // namespace viscera::session
