// Running the bowel's score in session_status_t: the running_ fields, written and read back
// exactly (FillStatus and ReportFromStatus call these), each field named once in a table.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "assessment/status_report.h"

namespace viscera::assessment {
namespace {

using viscera_proto::session_status_t;

// A figure of RunningReport and the status field that carries it.
template <typename Report, typename Status>
struct Field {
  Report RunningReport::*report;
  Status session_status_t::*status;
};

// RunningReport's `name` and the status's running_`name`
#define VISCERA_RUNNING_FIELD(name) \
  { &RunningReport::name, &session_status_t::running_##name }

constexpr Field<double, double> kDoubles[] = {VISCERA_RUNNING_FIELD(segment_length),
                                              VISCERA_RUNNING_FIELD(coverage),
                                              VISCERA_RUNNING_FIELD(path_length),
                                              VISCERA_RUNNING_FIELD(out_of_view_time),
                                              VISCERA_RUNNING_FIELD(time),
                                              VISCERA_RUNNING_FIELD(max_grip),
                                              VISCERA_RUNNING_FIELD(max_pressure),
                                              VISCERA_RUNNING_FIELD(max_traction),
                                              VISCERA_RUNNING_FIELD(max_dose),
                                              VISCERA_RUNNING_FIELD(run_length),
                                              VISCERA_RUNNING_FIELD(estimate_length),
                                              VISCERA_RUNNING_FIELD(estimate_error),
                                              VISCERA_RUNNING_FIELD(pinch_force),
                                              VISCERA_RUNNING_FIELD(damage_dose),
                                              VISCERA_RUNNING_FIELD(traction_break),
                                              VISCERA_RUNNING_FIELD(jaw_area),
                                              VISCERA_RUNNING_FIELD(pass_coverage),
                                              VISCERA_RUNNING_FIELD(pass_time),
                                              VISCERA_RUNNING_FIELD(pass_path),
                                              VISCERA_RUNNING_FIELD(pass_out_of_view),
                                              VISCERA_RUNNING_FIELD(pass_estimate_error)};

constexpr Field<int, int32_t> kInts[] = {
    VISCERA_RUNNING_FIELD(segments), VISCERA_RUNNING_FIELD(reversals),
    VISCERA_RUNNING_FIELD(pass_reversals), VISCERA_RUNNING_FIELD(pass_slips),
    VISCERA_RUNNING_FIELD(pass_damage_events)};

// counts the report keeps in 64 bits, the status in 32 (a session's are far below 2^31)
constexpr Field<int64_t, int32_t> kCounts[] = {
    VISCERA_RUNNING_FIELD(grasps), VISCERA_RUNNING_FIELD(regrasps), VISCERA_RUNNING_FIELD(slips),
    VISCERA_RUNNING_FIELD(instrument_collisions)};

#undef VISCERA_RUNNING_FIELD

// A list and its count, into a status.
template <typename T>
void Put(const std::vector<T>& from, int32_t* count, std::vector<T>* to) {
  *to = from;
  *count = static_cast<int32_t>(from.size());
}

// The first `count` of a status's list (no more than it holds: a status not decoded from the
// wire may disagree with its counts).
template <typename T>
std::vector<T> Take(int32_t count, const std::vector<T>& from) {
  const size_t n = std::min(static_cast<size_t>(std::max(count, 0)), from.size());
  return std::vector<T>(from.begin(), from.begin() + static_cast<std::ptrdiff_t>(n));
}

}  // namespace

void FillRunningStatus(const Report& report, session_status_t* s) {
  // no [running]: every field 0 or empty (the scored segments are never 0 with it)
  const RunningReport r = report.has_running ? report.running : RunningReport{};
  for (const auto& f : kDoubles) s->*f.status = r.*f.report;
  for (const auto& f : kInts) s->*f.status = r.*f.report;
  for (const auto& f : kCounts) s->*f.status = static_cast<int32_t>(r.*f.report);
  Put(r.missed, &s->running_num_missed, &s->running_missed);
  Put(r.damaged, &s->running_num_damaged, &s->running_damaged);
  Put(r.failed, &s->running_num_failed, &s->running_failed);
  s->running_passed = r.passed;
  s->running_num_events = static_cast<int32_t>(r.events.size());
  s->running_event_kinds.clear();
  s->running_event_segments.clear();
  s->running_event_tools.clear();
  s->running_event_times.clear();
  s->running_event_values.clear();
  for (const DamageEvent& e : r.events) {
    s->running_event_kinds.push_back(e.kind);
    s->running_event_segments.push_back(e.segment);
    s->running_event_tools.push_back(e.tool);
    s->running_event_times.push_back(e.t);
    s->running_event_values.push_back(e.value);
  }
}

bool RunningFromStatus(const session_status_t& s, RunningReport* r) {
  *r = RunningReport{};
  if (s.running_segments <= 0) return false;
  for (const auto& f : kDoubles) r->*f.report = s.*f.status;
  for (const auto& f : kInts) r->*f.report = s.*f.status;
  for (const auto& f : kCounts) r->*f.report = s.*f.status;
  r->missed = Take(s.running_num_missed, s.running_missed);
  r->damaged = Take(s.running_num_damaged, s.running_damaged);
  r->failed = Take(s.running_num_failed, s.running_failed);
  r->passed = s.running_passed;
  const size_t events = Take(s.running_num_events, s.running_event_values).size();
  for (size_t i = 0;
       i < events && i < s.running_event_kinds.size() && i < s.running_event_segments.size() &&
       i < s.running_event_tools.size() && i < s.running_event_times.size();
       ++i) {
    r->events.push_back({s.running_event_kinds[i], s.running_event_segments[i],
                         s.running_event_tools[i], s.running_event_times[i],
                         s.running_event_values[i]});
  }
  return true;
}

}  // namespace viscera::assessment
