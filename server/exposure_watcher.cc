#include "server/exposure_watcher.h"

#include <exception>
#include <vector>

#include "assessment/exposure.h"
#include "collision/sphere_chain.h"
#include "common/check.h"
#include "common/clock.h"
#include "server/idle_priority.h"
#include "server/session_view.h"

namespace viscera::server {

ExposureWatcher::ExposureWatcher(session::Session* session, ExposureWatchConfig config)
    : session_(session), config_(config) {
  VISCERA_DEMAND(session_ != nullptr);
}

ExposureWatcher::~ExposureWatcher() { Stop(); }

void ExposureWatcher::Start() {
  worker_.Start([this] { Run(); });
}

void ExposureWatcher::RequestStop() { worker_.RequestStop(); }

void ExposureWatcher::Stop() { worker_.Stop(); }

void ExposureWatcher::Run() {
  NiceThisThread();
  // An exception never crosses a thread: the session runs on without exposures and says why.
  try {
    const mechanics::Model& model = session_->model();
    const mechanics::ModelParams& params = model.params();
    const assessment::ExposureEvaluator evaluator(params.task.targets, params.radius);
    collision::SphereChain chain(model.curve(), params.length, params.radius);
    std::vector<Vec3> centres;
    render::Laparoscope framing;
    bool have_framing = false;
    int64_t shown_step = -1;
    const int64_t period = static_cast<int64_t>(1e9 / params.task.assessment.exposure_rate_hz);

    int64_t next = MonotonicNanos();
    while (worker_.SleepUntil(next)) {
      if (std::shared_ptr<const session::Snapshot> snapshot = session_->LatestSnapshot();
          snapshot != nullptr && snapshot->step != shown_step) {
        if (!have_framing) {
          framing = FirstFraming(params, snapshot->q, config_.width, config_.height);
          have_framing = true;
        }
        const render::Laparoscope scope = SessionScope(session_->camera(), framing);
        const assessment::View view{scope.eye.cast<double>(), scope.target.cast<double>(),
                                    scope.up.cast<double>(), scope.fov_y_degrees,
                                    static_cast<double>(config_.width) / config_.height};
        session_->ReportView(view);
        if (evaluator.num_targets() > 0) {
          chain.Place(snapshot->q);
          centres.clear();
          for (const collision::Sphere& s : chain.spheres()) centres.push_back(s.centre);
        }
        for (int i = 0; i < evaluator.num_targets(); ++i) {
          session_->ReportExposure(i, evaluator.Evaluate(i, view, centres).fraction, snapshot->t);
        }
        shown_step = snapshot->step;
        ++evaluations_;
      }
      next += period;
      const int64_t now = MonotonicNanos();
      if (next < now) next = now;  // late (a loaded machine): the next one from now, no burst
    }
  } catch (const std::exception& e) {
    session_->SetError(Cat("target exposure stopped: ", e.what()));
  }
  finished_ = true;
}

}  // namespace viscera::server
