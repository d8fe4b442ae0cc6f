// The running-the-bowel section of a report: its JSON and its text.
#include <cmath>
#include <cstdio>

#include "assessment/report.h"

namespace viscera::assessment {
namespace {

std::string Join(const std::vector<int>& xs) {
  std::string out;
  for (int x : xs) {
    if (!out.empty()) out += ' ';
    out += std::to_string(x);
  }
  return out.empty() ? "none" : out;
}

}  // namespace

nlohmann::json RunningToJson(const RunningReport& r) {
  nlohmann::json events = nlohmann::json::array();
  for (const DamageEvent& e : r.events) {
    events.push_back({{"kind", e.kind},
                      {"segment", e.segment},
                      {"tool", e.tool},
                      {"t_s", e.t},
                      {"value", e.value}});
  }
  return {{"segments", r.segments},
          {"segment_length_m", r.segment_length},
          {"coverage", r.coverage},
          {"missed", r.missed},
          {"reversals", r.reversals},
          {"grasps", r.grasps},
          {"regrasps", r.regrasps},
          {"slips", r.slips},
          {"path_length_m", r.path_length},
          {"instrument_collisions", r.instrument_collisions},
          {"out_of_view_time_s", r.out_of_view_time},
          {"time_s", r.time},
          {"max_grip_n", r.max_grip},
          {"max_pressure_pa", r.max_pressure},
          {"max_traction_n", r.max_traction},
          {"max_dose_ns", r.max_dose},
          {"events", events},
          {"damaged", r.damaged},
          {"run_length_m", r.run_length},
          {"estimate_length_m", r.estimate_length},
          {"estimate_error", r.estimate_error},
          {"passed", r.passed},
          {"failed", r.failed},
          {"thresholds",
           {{"pinch_force_n", r.pinch_force},
            {"damage_dose_ns", r.damage_dose},
            {"traction_break_n", r.traction_break},
            {"jaw_area_m2", r.jaw_area}}},
          {"pass_marks",
           {{"coverage", r.pass_coverage},
            {"time_s", r.pass_time},
            {"path_length_m", r.pass_path},
            {"out_of_view_time_s", r.pass_out_of_view},
            {"reversals", r.pass_reversals},
            {"slips", r.pass_slips},
            {"damage_events", r.pass_damage_events},
            {"estimate_error", r.pass_estimate_error}}}};
}

RunningReport RunningFromJson(const nlohmann::json& j) {
  RunningReport r;
  r.segments = j.at("segments").get<int>();
  r.segment_length = j.at("segment_length_m").get<double>();
  r.coverage = j.at("coverage").get<double>();
  r.missed = j.at("missed").get<std::vector<int>>();
  r.reversals = j.at("reversals").get<int>();
  r.grasps = j.at("grasps").get<int64_t>();
  r.regrasps = j.at("regrasps").get<int64_t>();
  r.slips = j.at("slips").get<int64_t>();
  r.path_length = j.at("path_length_m").get<double>();
  r.instrument_collisions = j.at("instrument_collisions").get<int64_t>();
  r.out_of_view_time = j.at("out_of_view_time_s").get<double>();
  r.time = j.at("time_s").get<double>();
  r.max_grip = j.at("max_grip_n").get<double>();
  r.max_pressure = j.at("max_pressure_pa").get<double>();
  r.max_traction = j.at("max_traction_n").get<double>();
  r.max_dose = j.at("max_dose_ns").get<double>();
  for (const nlohmann::json& e : j.at("events")) {
    r.events.push_back({e.at("kind").get<std::string>(), e.at("segment").get<int>(),
                        e.at("tool").get<std::string>(), e.at("t_s").get<double>(),
                        e.at("value").get<double>()});
  }
  r.damaged = j.at("damaged").get<std::vector<int>>();
  r.run_length = j.at("run_length_m").get<double>();
  r.estimate_length = j.at("estimate_length_m").get<double>();
  r.estimate_error = j.at("estimate_error").get<double>();
  r.passed = j.at("passed").get<bool>();
  r.failed = j.at("failed").get<std::vector<std::string>>();
  const nlohmann::json& th = j.at("thresholds");
  r.pinch_force = th.at("pinch_force_n").get<double>();
  r.damage_dose = th.at("damage_dose_ns").get<double>();
  r.traction_break = th.at("traction_break_n").get<double>();
  r.jaw_area = th.at("jaw_area_m2").get<double>();
  const nlohmann::json& pm = j.at("pass_marks");
  r.pass_coverage = pm.at("coverage").get<double>();
  r.pass_time = pm.at("time_s").get<double>();
  r.pass_path = pm.at("path_length_m").get<double>();
  // reports written before the mark have none: not judged
  r.pass_out_of_view = pm.value("out_of_view_time_s", 0.0);
  r.pass_reversals = pm.at("reversals").get<int>();
  r.pass_slips = pm.at("slips").get<int>();
  r.pass_damage_events = pm.at("damage_events").get<int>();
  r.pass_estimate_error = pm.at("estimate_error").get<double>();
  return r;
}

bool operator==(const DamageEvent& a, const DamageEvent& b) {
  return a.kind == b.kind && a.segment == b.segment && a.tool == b.tool && a.t == b.t &&
         a.value == b.value;
}

bool operator==(const RunningReport& a, const RunningReport& b) {
  return RunningToJson(a) == RunningToJson(b);  // every field is in the JSON
}

std::string FormatRunning(const RunningReport& r) {
  std::string out;
  char line[512];
  std::snprintf(line, sizeof line,
                "running          %s; coverage %.1f %% of %d segments of %.0f cm; missed %s\n",
                r.passed ? "PASS" : "FAIL", 100.0 * r.coverage, r.segments,
                100.0 * r.segment_length, Join(r.missed).c_str());
  out += line;
  std::snprintf(line, sizeof line,
                "  handling       %.1f s; path %.2f m; grasps %lld (regrasps %lld); slips %lld; "
                "reversals %d; instrument collisions %lld; out of view %.1f s\n",
                r.time, r.path_length, static_cast<long long>(r.grasps),
                static_cast<long long>(r.regrasps), static_cast<long long>(r.slips), r.reversals,
                static_cast<long long>(r.instrument_collisions), r.out_of_view_time);
  out += line;
  int pinch = 0, dose = 0, traction = 0;
  for (const DamageEvent& e : r.events) {
    pinch += e.kind == "pinch";
    dose += e.kind == "dose";
    traction += e.kind == "traction";
  }
  std::snprintf(
      line, sizeof line,
      "  tissue         grip max %.1f N (%.0f kPa); traction max %.1f N; dose max %.0f N s; "
      "events: pinch %d, dose %d, traction %d; damaged segments %s\n",
      r.max_grip, 1e-3 * r.max_pressure, r.max_traction, r.max_dose, pinch, dose, traction,
      Join(r.damaged).c_str());
  out += line;
  for (const DamageEvent& e : r.events) {
    std::snprintf(line, sizeof line,
                  "  event          %-8s segment %d (%.0f-%.0f cm), %s, t = %.2f s, %.1f %s\n",
                  e.kind.c_str(), e.segment, 100.0 * e.segment * r.segment_length,
                  100.0 * (e.segment + 1) * r.segment_length, e.tool.c_str(), e.t, e.value,
                  e.kind == "dose" ? "N s" : "N");
    out += line;
  }
  if (r.estimate_length > 0.0) {
    std::snprintf(
        line, sizeof line,
        "  estimate       asked %.0f cm, ran %.1f cm: error %+.1f %% (pass within %.0f %%)\n",
        100.0 * r.estimate_length, 100.0 * r.run_length, 100.0 * r.estimate_error,
        100.0 * r.pass_estimate_error);
    out += line;
  }
  std::snprintf(line, sizeof line,
                "  thresholds     pinch %.1f N, dose %.0f N s, traction %.1f N; pass at coverage "
                "%.0f %%, time %.0f s, path %.1f m, out of view %.0f s (0: not judged)\n",
                r.pinch_force, r.damage_dose, r.traction_break, 100.0 * r.pass_coverage,
                r.pass_time, r.pass_path, r.pass_out_of_view);
  out += line;
  if (!r.failed.empty()) {
    out += "  failed on      ";
    for (size_t i = 0; i < r.failed.size(); ++i) {
      if (i > 0) out += ", ";
      out += r.failed[i];
    }
    out += '\n';
  }
  return out;
}

}  // namespace viscera::assessment
