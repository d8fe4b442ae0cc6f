#include "sim/sim_assessment.h"

#include <algorithm>
#include <cmath>

#include "common/clock.h"

namespace viscera::tools {

SimAssessment::SimAssessment(const mechanics::Model& model, const assessment::View& view)
    : model_(model),
      params_(model.params()),
      view_(view),
      metrics_(params_),
      tracker_(model.params().task),
      evaluator_(model.params().task.targets, model.params().radius),
      chain_(model.curve(), model.params().length, model.params().radius) {
  const mechanics::ModelParams& p = model.params();
  every_ = std::max<int64_t>(1, std::llround(p.rate_hz / p.task.assessment.exposure_rate_hz));
  metrics_.SetView(view_);
}

void SimAssessment::EvaluateExposure(const mechanics::State& state) {
  if (evaluator_.num_targets() == 0) return;
  const int64_t begin = ThreadCpuNanos();
  chain_.Place(state.q);
  centres_.clear();
  for (const collision::Sphere& s : chain_.spheres()) centres_.push_back(s.centre);
  std::vector<double> row{state.t};
  for (int i = 0; i < evaluator_.num_targets(); ++i) {
    const assessment::TargetExposure e = evaluator_.Evaluate(i, view_, centres_);
    tracker_.Add(i, e.fraction, state.t);
    row.push_back(e.fraction);
    max_capsules_ = std::max(max_capsules_, e.capsules_tested);
  }
  const double us = static_cast<double>(ThreadCpuNanos() - begin) * 1e-3;
  exposure_us_ += us;
  exposure_max_us_ = std::max(exposure_max_us_, us);
  ++evaluations_;
  series_.push_back(std::move(row));
}

void SimAssessment::AddStep(const mechanics::State& state) {
  if (state.steps == last_step_) {
    if (state.steps == 0 && evaluations_ == 0) EvaluateExposure(state);  // the start
    return;
  }
  last_step_ = state.steps;
  metrics_.AddStep(state, model_.step_size());
  if (state.steps % every_ == 0) EvaluateExposure(state);
}

assessment::Report SimAssessment::Report(int64_t session, const std::string& scene) const {
  assessment::Report r;
  r.session = session;
  r.scene = scene;
  r.finished = true;
  metrics_.Fill(&r);
  tracker_.Fill(&r);
  return r;
}

}  // namespace viscera::tools
