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

struct Report {
  int64_t session = 0;
  std::string scene;
  double sim_time = 0.0;  ///< s simulated
  bool finished = false;  ///< the session had ended
  Thresholds thresholds;
  std::vector<ToolReport> tools;
  std::vector<TargetReport> targets;
};

nlohmann::json ToJson(const Report& report);
/// @throws nlohmann::json::exception when a key is missing or of the wrong type.
Report ReportFromJson(const nlohmann::json& json);
bool operator==(const ToolReport&, const ToolReport&);
bool operator==(const TargetReport&, const TargetReport&);
bool operator==(const Thresholds&, const Thresholds&);
bool operator==(const Report&, const Report&);

/// A human-readable table of the report (the text `viscera report` and viscera-sim print).
std::string FormatReport(const Report& report);

}  // namespace viscera::assessment
