#include "session/assessment_file.h"

#include <cstdio>
#include <fstream>

namespace viscera::session {

void TargetExposures::Add(int index, double exposure, double sim_time) {
  std::lock_guard<std::mutex> lock(mutex_);
  tracker_.Add(index, exposure, sim_time);
}

void TargetExposures::FillForStatus(bool may_wait, assessment::Report* report) {
  {
    // never wait for the exposure watcher: if it holds the lock, the targets last read serve
    std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
    if (lock.owns_lock() || may_wait) {
      if (!lock.owns_lock()) lock.lock();
      tracker_.Fill(&seen_);
    }
  }
  report->targets = seen_.targets;
}

void TargetExposures::SetView(const assessment::View& view) {
  std::lock_guard<std::mutex> lock(mutex_);
  view_ = view;
  views_.fetch_add(1, std::memory_order_release);
}

bool TargetExposures::TakeView(assessment::View* view) {
  const int64_t views = views_.load(std::memory_order_acquire);
  if (views == views_taken_) return false;
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return false;  // the next step tries again
  *view = view_;
  views_taken_ = views_.load(std::memory_order_relaxed);
  return true;
}

std::string AssessmentPathFor(const std::string& record_path) {
  std::string path = record_path;
  const std::string ext = ".lcmlog";
  if (path.size() > ext.size() && path.compare(path.size() - ext.size(), ext.size(), ext) == 0) {
    path.resize(path.size() - ext.size());
  }
  return path + ".assessment.json";
}

bool WriteAssessmentFile(const std::string& path, const assessment::Report& report) {
  // write then rename: a reader never sees half a report
  const std::string partial = path + ".partial";
  {
    std::ofstream out(partial);
    out << assessment::ToJson(report).dump(2) << "\n";
    if (!out) return false;
  }
  return std::rename(partial.c_str(), path.c_str()) == 0;
}

}  // namespace viscera::session
