#pragma once
/// The assessment of an offline run (viscera-sim): the session's per-step metrics and, every
/// few steps (the scene's exposure_rate), the exposure of each target from the run's camera —
/// what viscerad computes for a session, on the same code, for scripts and for checking a
/// session's report against its record.
#include <utility>
#include <vector>

#include "assessment/exposure.h"
#include "assessment/metrics.h"
#include "assessment/report.h"
#include "collision/sphere_chain.h"
#include "mechanics/model.h"
#include "mechanics/state.h"

namespace viscera::tools {

class SimAssessment {
 public:
  /// @pre model outlives every AddStep (Report needs it no longer: a replay's model is gone
  ///      when the replay returns).
  SimAssessment(const mechanics::Model& model, const assessment::View& view);

  /// The camera moved: exposures, camera coverage and the time out of view follow it.
  void SetView(const assessment::View& view) {
    view_ = view;
    metrics_.SetView(view);
  }
  /// Takes the state after a step (a repeated step count, e.g. after a reset, adds nothing).
  void AddStep(const mechanics::State& state);

  assessment::Report Report(int64_t session, const std::string& scene) const;
  /// Running the bowel's damaged segments as ranges of s, for the frames (empty without it).
  std::vector<std::pair<double, double>> DamagedRanges() const {
    return metrics_.running() ? metrics_.running()->damage().DamagedRanges()
                              : std::vector<std::pair<double, double>>{};
  }
  /// (simulated time, exposure of each target) at each evaluation.
  const std::vector<std::vector<double>>& exposure_series() const { return series_; }
  /// CPU time of the exposure evaluations (all targets), mean and max (us).
  double exposure_mean_us() const { return evaluations_ > 0 ? exposure_us_ / evaluations_ : 0.0; }
  double exposure_max_us() const { return exposure_max_us_; }
  /// Capsules left after the cone cull, largest over the evaluations; samples per evaluation.
  int max_capsules_tested() const { return max_capsules_; }

 private:
  void EvaluateExposure(const mechanics::State& state);

  const mechanics::Model& model_;
  mechanics::ModelParams params_;  // the metrics' own copy
  assessment::View view_;
  assessment::SessionMetrics metrics_;
  assessment::TargetTracker tracker_;
  assessment::ExposureEvaluator evaluator_;
  collision::SphereChain chain_;
  std::vector<Vec3> centres_;
  int64_t every_ = 1;
  int64_t last_step_ = 0;
  std::vector<std::vector<double>> series_;
  double exposure_us_ = 0.0, exposure_max_us_ = 0.0;
  int64_t evaluations_ = 0;
  int max_capsules_ = 0;
};

}  // namespace viscera::tools
