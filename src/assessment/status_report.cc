#include "assessment/status_report.h"

#include <cassert>

namespace viscera::assessment {

using viscera_proto::session_status_t;

void FillStatus(const Report& report, session_status_t* s) {
  assert(static_cast<int>(report.tools.size()) == s->num_tools);
  const size_t n = report.tools.size();
  s->tool_path_length.resize(n);
  s->tool_active_time.resize(n);
  s->tool_force_p50.resize(n);
  s->tool_force_p95.resize(n);
  s->tool_force_max.resize(n);
  s->tool_contact_time.resize(n);
  s->tool_traction_events.resize(n);
  s->tool_traction_time.resize(n);
  s->tool_grasps.resize(n);
  s->tool_regrasps.resize(n);
  s->tool_organ_contacts.resize(n);
  s->tool_organ_contact_time.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const ToolReport& t = report.tools[i];
    s->tool_path_length[i] = t.path_length;
    s->tool_active_time[i] = t.active_time;
    s->tool_force_p50[i] = t.force_p50;
    s->tool_force_p95[i] = t.force_p95;
    s->tool_force_max[i] = t.force_max;
    s->tool_contact_time[i] = t.contact_time;
    s->tool_traction_events[i] = static_cast<int32_t>(t.traction_events);
    s->tool_traction_time[i] = t.traction_time;
    s->tool_grasps[i] = static_cast<int32_t>(t.grasps);
    s->tool_regrasps[i] = static_cast<int32_t>(t.regrasps);
    s->tool_organ_contacts[i] = static_cast<int32_t>(t.organ_contacts);
    s->tool_organ_contact_time[i] = t.organ_contact_time;
  }
  s->num_targets = static_cast<int32_t>(report.targets.size());
  s->target_names.clear();
  s->target_exposed.clear();
  s->target_max_exposed.clear();
  s->target_time_to_expose.clear();
  for (const TargetReport& t : report.targets) {
    s->target_names.push_back(t.name);
    s->target_exposed.push_back(t.exposed);
    s->target_max_exposed.push_back(t.max_exposed);
    s->target_time_to_expose.push_back(t.time_to_expose);
  }
  s->traction_force = report.thresholds.traction_force;
  s->traction_hold = report.thresholds.traction_hold;
  s->regrasp_window = report.thresholds.regrasp_window;
  s->exposed_fraction = report.thresholds.exposed_fraction;
  FillRunningStatus(report, s);
}

Report ReportFromStatus(const session_status_t& s) {
  Report r;
  r.session = s.header.session_id;
  r.scene = s.scene;
  r.sim_time = s.sim_time;
  r.finished = s.state == session_status_t::kStopped || s.state == session_status_t::kFaulted;
  r.thresholds = {s.traction_force, s.traction_hold, s.regrasp_window, s.exposed_fraction};
  for (size_t i = 0; i < static_cast<size_t>(s.num_tools) && i < s.tool_path_length.size(); ++i) {
    ToolReport t;
    t.name = i < s.tool_names.size() ? s.tool_names[i] : std::string();
    t.path_length = s.tool_path_length[i];
    t.active_time = s.tool_active_time[i];
    t.force_p50 = s.tool_force_p50[i];
    t.force_p95 = s.tool_force_p95[i];
    t.force_max = s.tool_force_max[i];
    t.contact_time = s.tool_contact_time[i];
    t.traction_events = s.tool_traction_events[i];
    t.traction_time = s.tool_traction_time[i];
    t.grasps = s.tool_grasps[i];
    t.regrasps = s.tool_regrasps[i];
    t.organ_contacts = s.tool_organ_contacts[i];
    t.organ_contact_time = s.tool_organ_contact_time[i];
    r.tools.push_back(t);
  }
  for (size_t i = 0; i < static_cast<size_t>(s.num_targets); ++i) {
    r.targets.push_back({s.target_names[i], s.target_exposed[i], s.target_max_exposed[i],
                         s.target_time_to_expose[i]});
  }
  r.has_running = RunningFromStatus(s, &r.running);
  return r;
}

}  // namespace viscera::assessment
