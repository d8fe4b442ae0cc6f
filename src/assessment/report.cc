#include "assessment/report.h"

#include <cstdio>

namespace viscera::assessment {

nlohmann::json ToJson(const Report& r) {
  nlohmann::json tools = nlohmann::json::array();
  for (const ToolReport& t : r.tools) {
    tools.push_back(
        {{"name", t.name},
         {"path_length_m", t.path_length},
         {"active_time_s", t.active_time},
         {"tissue_force_n", {{"p50", t.force_p50}, {"p95", t.force_p95}, {"max", t.force_max}}},
         {"tissue_contact_time_s", t.contact_time},
         {"traction_events", t.traction_events},
         {"traction_time_s", t.traction_time},
         {"grasps", t.grasps},
         {"regrasps", t.regrasps},
         {"organ_contacts", t.organ_contacts},
         {"organ_contact_time_s", t.organ_contact_time}});
  }
  nlohmann::json targets = nlohmann::json::array();
  for (const TargetReport& t : r.targets) {
    targets.push_back(
        {{"name", t.name},
         {"exposed", t.exposed},
         {"max_exposed", t.max_exposed},
         {"time_to_expose_s",
          t.time_to_expose >= 0.0 ? nlohmann::json(t.time_to_expose) : nlohmann::json(nullptr)}});
  }
  return {{"session", r.session},
          {"scene", r.scene},
          {"sim_time_s", r.sim_time},
          {"finished", r.finished},
          {"thresholds",
           {{"traction_force_n", r.thresholds.traction_force},
            {"traction_hold_s", r.thresholds.traction_hold},
            {"regrasp_window_s", r.thresholds.regrasp_window},
            {"exposed_fraction", r.thresholds.exposed_fraction}}},
          {"tools", tools},
          {"targets", targets},
          {"running", r.has_running ? RunningToJson(r.running) : nlohmann::json(nullptr)}};
}

Report ReportFromJson(const nlohmann::json& j) {
  Report r;
  r.session = j.at("session").get<int64_t>();
  r.scene = j.at("scene").get<std::string>();
  r.sim_time = j.at("sim_time_s").get<double>();
  r.finished = j.at("finished").get<bool>();
  const nlohmann::json& th = j.at("thresholds");
  r.thresholds.traction_force = th.at("traction_force_n").get<double>();
  r.thresholds.traction_hold = th.at("traction_hold_s").get<double>();
  r.thresholds.regrasp_window = th.at("regrasp_window_s").get<double>();
  r.thresholds.exposed_fraction = th.at("exposed_fraction").get<double>();
  for (const nlohmann::json& t : j.at("tools")) {
    ToolReport x;
    x.name = t.at("name").get<std::string>();
    x.path_length = t.at("path_length_m").get<double>();
    x.active_time = t.at("active_time_s").get<double>();
    x.force_p50 = t.at("tissue_force_n").at("p50").get<double>();
    x.force_p95 = t.at("tissue_force_n").at("p95").get<double>();
    x.force_max = t.at("tissue_force_n").at("max").get<double>();
    x.contact_time = t.at("tissue_contact_time_s").get<double>();
    x.traction_events = t.at("traction_events").get<int64_t>();
    x.traction_time = t.at("traction_time_s").get<double>();
    x.grasps = t.at("grasps").get<int64_t>();
    x.regrasps = t.at("regrasps").get<int64_t>();
    x.organ_contacts = t.at("organ_contacts").get<int64_t>();
    x.organ_contact_time = t.at("organ_contact_time_s").get<double>();
    r.tools.push_back(x);
  }
  for (const nlohmann::json& t : j.at("targets")) {
    TargetReport x;
    x.name = t.at("name").get<std::string>();
    x.exposed = t.at("exposed").get<double>();
    x.max_exposed = t.at("max_exposed").get<double>();
    x.time_to_expose =
        t.at("time_to_expose_s").is_null() ? -1.0 : t.at("time_to_expose_s").get<double>();
    r.targets.push_back(x);
  }
  // reports written before the running task have no "running"
  if (j.contains("running") && !j.at("running").is_null()) {
    r.has_running = true;
    r.running = RunningFromJson(j.at("running"));
  }
  return r;
}

bool operator==(const ToolReport& a, const ToolReport& b) {
  return a.name == b.name && a.path_length == b.path_length && a.active_time == b.active_time &&
         a.force_p50 == b.force_p50 && a.force_p95 == b.force_p95 && a.force_max == b.force_max &&
         a.contact_time == b.contact_time && a.traction_events == b.traction_events &&
         a.traction_time == b.traction_time && a.grasps == b.grasps && a.regrasps == b.regrasps &&
         a.organ_contacts == b.organ_contacts && a.organ_contact_time == b.organ_contact_time;
}
bool operator==(const TargetReport& a, const TargetReport& b) {
  return a.name == b.name && a.exposed == b.exposed && a.max_exposed == b.max_exposed &&
         a.time_to_expose == b.time_to_expose;
}
bool operator==(const Thresholds& a, const Thresholds& b) {
  return a.traction_force == b.traction_force && a.traction_hold == b.traction_hold &&
         a.regrasp_window == b.regrasp_window && a.exposed_fraction == b.exposed_fraction;
}
bool operator==(const Report& a, const Report& b) {
  return a.session == b.session && a.scene == b.scene && a.sim_time == b.sim_time &&
         a.finished == b.finished && a.thresholds == b.thresholds && a.tools == b.tools &&
         a.targets == b.targets && a.has_running == b.has_running &&
         (!a.has_running || a.running == b.running);
}

std::string FormatReport(const Report& r) {
  std::string out;
  char line[512];
  std::snprintf(line, sizeof line, "assessment       session %lld, scene %s, %.2f s simulated%s\n",
                static_cast<long long>(r.session), r.scene.c_str(), r.sim_time,
                r.finished ? " (ended)" : " (running)");
  out += line;
  std::snprintf(line, sizeof line,
                "thresholds       traction above %.2f N held %.2f s; regrasp within %.2f s; "
                "exposed at %.0f %%\n",
                r.thresholds.traction_force, r.thresholds.traction_hold,
                r.thresholds.regrasp_window, 100.0 * r.thresholds.exposed_fraction);
  out += line;
  for (const ToolReport& t : r.tools) {
    std::snprintf(line, sizeof line,
                  "tool %-11s path %.3f m in %.2f s; tissue force p50 %.2f / p95 %.2f / max %.2f N "
                  "over %.2f s; "
                  "traction events %lld (%.2f s); grasps %lld (regrasps %lld); organ contacts %lld "
                  "(%.2f s)\n",
                  t.name.c_str(), t.path_length, t.active_time, t.force_p50, t.force_p95,
                  t.force_max, t.contact_time, static_cast<long long>(t.traction_events),
                  t.traction_time, static_cast<long long>(t.grasps),
                  static_cast<long long>(t.regrasps), static_cast<long long>(t.organ_contacts),
                  t.organ_contact_time);
    out += line;
  }
  for (const TargetReport& t : r.targets) {
    if (t.time_to_expose >= 0.0) {
      std::snprintf(line, sizeof line,
                    "target %-9s exposed %.0f %% (max %.0f %%), exposed at t = %.2f s\n",
                    t.name.c_str(), 100.0 * t.exposed, 100.0 * t.max_exposed, t.time_to_expose);
    } else {
      std::snprintf(line, sizeof line,
                    "target %-9s exposed %.0f %% (max %.0f %%), not exposed yet\n", t.name.c_str(),
                    100.0 * t.exposed, 100.0 * t.max_exposed);
    }
    out += line;
  }
  if (r.has_running) out += FormatRunning(r.running);
  return out;
}

}  // namespace viscera::assessment
