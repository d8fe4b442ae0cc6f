#pragma once
/// The assessment of one session as a value: per tool and per target figures, the thresholds
/// they were judged by, and its JSON form (the file written next to the session's record and
/// `viscera report --json`). Depends on nothing but nlohmann::json, so the client can read it.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace viscera::assessment {

struct ToolReport {
  std::string name;
  double path_length = 0.0;  ///< m travelled by the simulated tip while in the body
  double active_time = 0.0;  ///< s the tool was driven (a device or script gave targets)
  double force_p50 = 0.0;    ///< N on the tissue, over the steps the tool touched or held it
  double force_p95 = 0.0;
  double force_max = 0.0;
  double contact_time = 0.0;    ///< s touching or holding the intestine
  int64_t traction_events = 0;  ///< times the force stayed above the threshold for the hold time
  double traction_time = 0.0;   ///< s above the threshold in all
  int64_t grasps = 0;           ///< grasps of the intestine
  int64_t regrasps = 0;         ///< of those, started within the regrasp window after a release
  int64_t organ_contacts = 0;   ///< times the jaws touched another organ or the cavity wall
  double organ_contact_time = 0.0;  ///< s in such contact
};

struct TargetReport {
  std::string name;
  double exposed = 0.0;      ///< latest exposure, 0..1
  double max_exposed = 0.0;  ///< largest seen so far
  double time_to_expose =
      -1.0;  ///< simulated s at which exposure first reached the threshold; < 0: not yet
};

struct Thresholds {
  double traction_force = 0.0;    ///< N
  double traction_hold = 0.0;     ///< s
  double regrasp_window = 0.0;    ///< s
  double exposed_fraction = 0.0;  ///< 0..1
};

/// A tissue-damage event of running the bowel (docs/training.md).
struct DamageEvent {
  std::string kind;  ///< "pinch" (grip above the perforation force), "dose" (grip x time above
                     ///< the damage dose) or "traction" (pull above the breaking force)
  int segment = 0;   ///< the segment it hurt (0 at the duodenojejunal end)
  std::string tool;
  double t = 0.0;      ///< simulated s
  double value = 0.0;  ///< N for pinch and traction, N s for dose
};

/// Running the bowel: coverage, handling and damage, and the pass marks they are judged by.
struct RunningReport {
  int segments = 0;             ///< scored segments along the bowel
  double segment_length = 0.0;  ///< m
  double coverage = 0.0;        ///< fraction of the segments inspected (jaws or close camera)
  std::vector<int> missed;      ///< segments not inspected, in order
  int reversals = 0;            ///< times the run turned back along the bowel
  int64_t grasps = 0, regrasps = 0, slips = 0;  ///< both tools
  double path_length = 0.0;                     ///< m, both tools (each tool's is in Report::tools)
  int64_t instrument_collisions = 0;            ///< times the two shafts touched
  double out_of_view_time = 0.0;  ///< s a driven tool's tip was outside the camera's view
  double time = 0.0;              ///< s from the first grasp to the last release
  double max_grip = 0.0;          ///< N, the firmest grip
  double max_pressure = 0.0;      ///< Pa, the largest jaw pressure (grip / jaw area)
  double max_traction = 0.0;      ///< N, the largest pull on the bowel
  double max_dose = 0.0;          ///< N s, the largest grip x time on one segment
  std::vector<DamageEvent> events;
  std::vector<int> damaged;      ///< segments with a damage event, in order
  double run_length = 0.0;       ///< m of bowel between the first and the last grasp
  double estimate_length = 0.0;  ///< m asked for (0: not the length-estimation variant)
  double estimate_error = 0.0;   ///< (run_length - estimate_length) / estimate_length
  bool passed = false;
  std::vector<std::string> failed;  ///< the marks missed: "coverage", "damage", "time", ...
  // the thresholds and pass marks
  double pinch_force = 0.0, damage_dose = 0.0, traction_break = 0.0, jaw_area = 0.0;
  double pass_coverage = 0.0, pass_time = 0.0, pass_path = 0.0, pass_out_of_view = 0.0;
  double pass_estimate_error = 0.0;
  int pass_reversals = 0, pass_slips = 0, pass_damage_events = 0;
};

struct Report {
  int64_t session = 0;
  std::string scene;
  double sim_time = 0.0;  ///< s simulated
  bool finished = false;  ///< the session had ended
  Thresholds thresholds;
  std::vector<ToolReport> tools;
  std::vector<TargetReport> targets;
  bool has_running = false;  ///< the scene has the running-the-bowel task
  RunningReport running;
};

nlohmann::json ToJson(const Report& report);
/// @throws nlohmann::json::exception when a key is missing or of the wrong type.
Report ReportFromJson(const nlohmann::json& json);
bool operator==(const ToolReport&, const ToolReport&);
bool operator==(const TargetReport&, const TargetReport&);
bool operator==(const Thresholds&, const Thresholds&);
bool operator==(const DamageEvent&, const DamageEvent&);
bool operator==(const RunningReport&, const RunningReport&);
bool operator==(const Report&, const Report&);

nlohmann::json RunningToJson(const RunningReport& running);
/// @throws nlohmann::json::exception when a key is missing or of the wrong type.
RunningReport RunningFromJson(const nlohmann::json& json);
/// The running-the-bowel section of FormatReport.
std::string FormatRunning(const RunningReport& running);

/// A human-readable table of the report (the text `viscera report` and viscera-sim print).
std::string FormatReport(const Report& report);

}  // namespace viscera::assessment
