#pragma once
/// Per-step handling metrics of one session (docs/assessment.md): fed with the state each step
/// leaves (tips, tissue forces, grasps), never inside Step. O(tools x obstacles) per step,
/// allocation-free after construction; force percentiles from a fixed histogram (0.01 N bins).
#include <cstdint>
#include <memory>
#include <vector>

#include "assessment/report.h"
#include "assessment/running.h"
#include "mechanics/model_params.h"
#include "mechanics/state.h"

namespace viscera::assessment {

/// Tissue-force histogram: bins of kForceBin up to kForceRange, one overflow bin; the maximum
/// is kept exactly. A quantile is the centre of its bin (within half a bin, 0.005 N).
class ForceHistogram {
 public:
  static constexpr double kForceBin = 0.01;    // N
  static constexpr double kForceRange = 50.0;  // N
  ForceHistogram();
  void Add(double force);
  /// q in [0, 1]; 0 when empty.
  double Quantile(double q) const;
  double max() const { return max_; }
  int64_t count() const { return count_; }

 private:
  std::vector<int64_t> bins_;
  int64_t count_ = 0;
  double max_ = 0.0;
};

class SessionMetrics {
 public:
  /// @pre `params` is valid (a Model was built from it) and outlives this.
  explicit SessionMetrics(const mechanics::ModelParams& params);

  /// Takes the state one step of `dt` seconds left.
  void AddStep(const mechanics::State& state, double dt);

  /// Tool figures so far, and running the bowel's when the scene sets it (targets are filled by
  /// TargetTracker).
  void Fill(Report* report) const;
  /// The camera, for running the bowel's camera coverage and time out of view.
  void SetView(const View& view) {
    if (running_) running_->SetView(view);
  }
  /// Running the bowel's score (null when the scene has no [running]).
  const RunningScore* running() const { return running_.get(); }

 private:
  struct Tool {
    bool had_tip = false;
    Vec3 last_tip = Vec3::Zero();
    double path = 0.0, active = 0.0, contact = 0.0;
    ForceHistogram force;
    double above = 0.0;    // s the force has been above the threshold, this run
    bool counted = false;  // this run already made an event
    int64_t traction_events = 0;
    double traction_time = 0.0;
    bool grasping = false;
    double released_at = -1.0;
    int64_t grasps = 0, regrasps = 0;
    bool touching_organ = false;
    int64_t organ_contacts = 0;
    double organ_time = 0.0;
  };
  bool TouchesOrgan(const Vec3& tip, double radius) const;

  const mechanics::ModelParams& params_;
  std::vector<Tool> tools_;
  double time_ = 0.0;
  std::unique_ptr<RunningScore> running_;
};

/// Exposure over time of each target: the latest, the largest and when it first reached the
/// threshold (simulated time of the pose evaluated).
class TargetTracker {
 public:
  explicit TargetTracker(const mechanics::TaskParams& task);
  void Add(int index, double exposure, double sim_time);
  void Fill(Report* report) const;

 private:
  double threshold_;
  std::vector<TargetReport> targets_;
};

/// Thresholds of a scene's [assessment] as the report states them.
Thresholds ThresholdsOf(const mechanics::AssessmentParams& a);

}  // namespace viscera::assessment
