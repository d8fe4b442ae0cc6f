#include "assessment/metrics.h"

#include <algorithm>
#include <cmath>

#include "collision/obstacle.h"

namespace viscera::assessment {

ForceHistogram::ForceHistogram()
    : bins_(static_cast<size_t>(std::lround(kForceRange / kForceBin)) + 1, 0) {}

void ForceHistogram::Add(double force) {
  if (!std::isfinite(force)) return;
  const double f = std::max(force, 0.0);
  const size_t bin = std::min(bins_.size() - 1, static_cast<size_t>(f / kForceBin));
  ++bins_[bin];
  ++count_;
  max_ = std::max(max_, f);
}

double ForceHistogram::Quantile(double q) const {
  if (count_ == 0) return 0.0;
  // the smallest bin whose cumulative count reaches ceil(q n) (nearest-rank)
  const int64_t rank =
      std::max<int64_t>(1, static_cast<int64_t>(std::ceil(q * static_cast<double>(count_))));
  int64_t seen = 0;
  for (size_t i = 0; i < bins_.size(); ++i) {
    seen += bins_[i];
    if (seen >= rank)
      return i + 1 == bins_.size() ? max_
                                   : std::min(max_, (static_cast<double>(i) + 0.5) * kForceBin);
  }
  return max_;
}

Thresholds ThresholdsOf(const mechanics::AssessmentParams& a) {
  return {a.traction_force, a.traction_hold, a.regrasp_window, a.exposed_fraction};
}

SessionMetrics::SessionMetrics(const mechanics::ModelParams& params)
    : params_(params), tools_(params.tools.size()) {
  if (params.task.running) running_ = std::make_unique<RunningScore>(params);
}

bool SessionMetrics::TouchesOrgan(const Vec3& tip, double radius) const {
  Vec3 normal;
  for (const collision::Obstacle& o : params_.obstacles) {
    if (collision::SignedDistance(o, tip, &normal) < radius) return true;
  }
  return false;
}

void SessionMetrics::AddStep(const mechanics::State& state, double dt) {
  time_ += dt;
  const mechanics::AssessmentParams& a = params_.task.assessment;
  for (size_t i = 0; i < tools_.size() && i < state.tools.size(); ++i) {
    const mechanics::ToolState& ts = state.tools[i];
    Tool& t = tools_[i];
    if (!ts.initialized) continue;
    // path of the simulated tip (what the instrument did, not the hand)
    if (t.had_tip) t.path += (ts.tip - t.last_tip).norm();
    t.last_tip = ts.tip;
    t.had_tip = true;
    if (ts.target.active) t.active += dt;

    // force on the tissue, over the steps the tool touches or holds the intestine
    const double f = ts.tissue_force.norm();
    if (f > 0.0) {
      t.force.Add(f);
      t.contact += dt;
    }
    // traction: one event per excursion above the threshold that lasts the hold time
    if (f > a.traction_force) {
      t.above += dt;
      t.traction_time += dt;
      if (!t.counted && t.above >= a.traction_hold - 1e-9) {
        ++t.traction_events;
        t.counted = true;
      }
    } else {
      t.above = 0.0;
      t.counted = false;
    }
    // grasps, and regrasps: a grasp soon after a release (the hold was lost or retried)
    if (ts.grasping && !t.grasping) {
      ++t.grasps;
      if (t.released_at >= 0.0 && time_ - t.released_at <= a.regrasp_window + 1e-9) ++t.regrasps;
    } else if (!ts.grasping && t.grasping) {
      t.released_at = time_;
    }
    t.grasping = ts.grasping;
    // the jaws (a sphere of the tool's radius at the tip) against other organs and the wall
    const bool touching = TouchesOrgan(ts.tip, params_.tools[i].radius);
    if (touching && !t.touching_organ) ++t.organ_contacts;
    if (touching) t.organ_time += dt;
    t.touching_organ = touching;
  }
  if (running_) running_->AddStep(state, dt);
}

void SessionMetrics::Fill(Report* report) const {
  report->tools.clear();
  for (size_t i = 0; i < tools_.size(); ++i) {
    const Tool& t = tools_[i];
    ToolReport r;
    r.name = params_.tools[i].name;
    r.path_length = t.path;
    r.active_time = t.active;
    r.force_p50 = t.force.Quantile(0.50);
    r.force_p95 = t.force.Quantile(0.95);
    r.force_max = t.force.max();
    r.contact_time = t.contact;
    r.traction_events = t.traction_events;
    r.traction_time = t.traction_time;
    r.grasps = t.grasps;
    r.regrasps = t.regrasps;
    r.organ_contacts = t.organ_contacts;
    r.organ_contact_time = t.organ_time;
    report->tools.push_back(r);
  }
  report->sim_time = std::max(report->sim_time, time_);
  report->thresholds = ThresholdsOf(params_.task.assessment);
  report->has_running = running_ != nullptr;
  if (running_) running_->Fill(&report->running);
}

TargetTracker::TargetTracker(const mechanics::TaskParams& task)
    : threshold_(task.assessment.exposed_fraction) {
  for (const mechanics::TargetParams& t : task.targets)
    targets_.push_back({t.name, 0.0, 0.0, -1.0});
}

void TargetTracker::Add(int index, double exposure, double sim_time) {
  TargetReport& t = targets_[static_cast<size_t>(index)];
  t.exposed = exposure;
  t.max_exposed = std::max(t.max_exposed, exposure);
  if (t.time_to_expose < 0.0 && exposure >= threshold_ - 1e-12) t.time_to_expose = sim_time;
}

void TargetTracker::Fill(Report* report) const { report->targets = targets_; }

}  // namespace viscera::assessment
