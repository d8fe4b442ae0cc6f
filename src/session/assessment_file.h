#pragma once
/// The assessment a session keeps beside its record: the exposures of its targets and the
/// camera they were judged from (reported by the exposure watcher's thread, read by the
/// mechanics thread without waiting), and the JSON file written when the session stops.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

#include "assessment/metrics.h"
#include "assessment/report.h"
#include "mechanics/task_params.h"

namespace viscera::session {

class TargetExposures {
 public:
  explicit TargetExposures(const mechanics::TaskParams& task) : tracker_(task) {}

  /// Keeps an exposure of target `index` (0..1) evaluated at simulated time `sim_time`
  /// (the exposure watcher's thread).
  void Add(int index, double exposure, double sim_time);
  /// The targets into `report` for a status (mechanics thread): the latest when the watcher
  /// does not hold the lock, or `may_wait` (the loop is over: waiting delays no step), else
  /// the ones last read.
  void FillForStatus(bool may_wait, assessment::Report* report);

  /// Keeps the camera the frames are drawn from (the exposure watcher's thread): running the
  /// bowel's camera coverage and time out of view are judged from it.
  void SetView(const assessment::View& view);
  /// The camera last set, into `*view`, when one was set since the last call and the watcher
  /// does not hold the lock (mechanics thread: it never waits); else false.
  bool TakeView(assessment::View* view);

 private:
  std::mutex mutex_;                   // the exposure watcher; the mechanics thread try_locks
  assessment::TargetTracker tracker_;  // guarded by mutex_
  assessment::View view_;              // guarded by mutex_
  std::atomic<int64_t> views_{0};      // views set so far
  assessment::Report seen_;            // mechanics thread: the targets it last could read
  int64_t views_taken_ = 0;            // mechanics thread: views_ at its last TakeView
};

/// Where the final assessment of a session recorded at `record_path` is written: the path
/// with `.assessment.json` for `.lcmlog` (appended to any other name).
std::string AssessmentPathFor(const std::string& record_path);

/// Writes `report` as JSON to `path`, whole or not at all (written aside, then renamed).
/// @return false when it could not be written.
bool WriteAssessmentFile(const std::string& path, const assessment::Report& report);

}  // namespace viscera::session
