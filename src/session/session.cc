#include "session/session.h"

#include <pthread.h>
#include <sched.h>

#include <cstring>

#include <algorithm>
#include <exception>
#include <limits>
#include <utility>

#include "assessment/metrics.h"
#include "assessment/status_report.h"
#include "bus/channels.h"
#include "bus/header.h"
#include "common/check.h"
#include "session/mechanics_loop.h"

namespace viscera::session {

using viscera_proto::session_status_t;

namespace {

// The status read before the mechanics thread posts one: who the session is, and the
// assessment's arrays sized by num_tools and num_targets from the first status on.
session_status_t FirstStatus(const SessionConfig& config, const mechanics::Model& model) {
  session_status_t status{};  // zeroed: lcm-gen types leave counters uninitialized
  status.header = bus::MakeHeader(config.id, 0);
  status.server_id = config.server_id;
  status.scene = config.scene;
  status.num_tools = static_cast<int>(model.params().tools.size());
  for (const mechanics::ToolParams& t : model.params().tools) status.tool_names.push_back(t.name);
  status.state = session_status_t::kRunning;
  status.rate_hz = model.params().rate_hz;
  assessment::Report empty;
  assessment::SessionMetrics(model.params()).Fill(&empty);
  assessment::TargetTracker(model.params().task).Fill(&empty);
  assessment::FillStatus(empty, &status);
  return status;
}

}  // namespace

Session::Session(SessionConfig config, std::shared_ptr<const mechanics::Model> model,
                 bus::LcmBus* bus, std::unique_ptr<Recorder> recorder)
    : config_(std::move(config)),
      model_(std::move(model)),
      bus_(bus),
      recorder_(std::move(recorder)),
      inbox_(static_cast<int>(model_->params().tools.size())),
      last_touch_ns_(MonotonicNanos()),
      board_(FirstStatus(config_, *model_)),
      targets_(model_->params().task) {
  VISCERA_DEMAND(config_.id > 0 && config_.status_rate_hz > 0.0 && config_.snapshot_rate_hz > 0.0 &&
                 bus_ != nullptr);
}

Session::~Session() { Stop(); }

void Session::Start() {
  VISCERA_DEMAND(!thread_.joinable());
  thread_ = std::thread([this] { Run(); });
}

void Session::Stop() {
  if (stop_.exchange(true)) return;
  if (thread_.joinable()) thread_.join();
  // the loop is over: its state is ours now. A last status, recorded, and the record flushed.
  board_.set_state(session_status_t::kStopped);
  try {
    PublishStatus(MonotonicNanos(), /*summarize=*/false);
  } catch (const std::exception& e) {
    SetError(Cat("final status failed: ", e.what()));
  }
  if (loop_ != nullptr) loop_->CloseOutbox();  // sends what is queued, joins its thread
  if (recorder_ != nullptr) recorder_->Flush();
  WriteAssessment();
}

void Session::ReportExposure(int index, double exposure, double sim_time) {
  targets_.Add(index, exposure, sim_time);
}

assessment::Report Session::Assessment() const { return assessment::ReportFromStatus(Status()); }

std::string Session::AssessmentPath() const {
  return recorder_ == nullptr ? "" : AssessmentPathFor(recorder_->path());
}

void Session::WriteAssessment() {
  const std::string path = AssessmentPath();
  if (path.empty()) return;
  if (!WriteAssessmentFile(path, Assessment())) SetError(Cat("assessment not written to ", path));
}

void Session::CountRejected(const std::string& why) { board_.CountRejected(why); }

void Session::CountReplayed(const std::string& why) { board_.CountReplayed(why); }

double Session::LeaseLeft(int64_t now_ns) const {
  if (config_.lease_s <= 0.0) return std::numeric_limits<double>::infinity();
  return config_.lease_s - static_cast<double>(now_ns - last_touch_ns_.load()) * 1e-9;
}

void Session::SetError(const std::string& why) { board_.SetError(why); }

void Session::ReportFrames(const FrameStreamReport& report) { board_.ReportFrames(report); }

session_status_t Session::Status() const {
  session_status_t s = board_.Read();
  s.lease_s = std::max(config_.lease_s, 0.0);
  s.lease_left_s = config_.lease_s > 0.0 ? std::max(LeaseLeft(MonotonicNanos()), 0.0) : 0.0;
  return s;
}

CameraPose Session::camera() const {
  std::lock_guard<std::mutex> lock(camera_mutex_);
  return camera_;
}

void Session::SetCamera(const CameraPose& pose) {
  std::lock_guard<std::mutex> lock(camera_mutex_);
  camera_ = pose;
}

void Session::Run() {
  bool realtime = false;
  if (config_.realtime_priority > 0) {
    sched_param param{};
    // one above the I/O, LCM and output threads (which run at realtime_priority): on two
    // cores a step must not wait for them to block
    param.sched_priority = std::min(99, config_.realtime_priority + 1);
    if (const int err = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param); err != 0) {
      SetError(Cat("realtime priority refused (", std::strerror(err), "): normal scheduling"));
    } else {
      realtime = true;
    }
  }
  // An exception never crosses a thread: the session is faulted, the daemon lives on.
  try {
    loop_ = std::make_unique<MechanicsLoop>(MechanicsLoop::Parts{
        &config_, model_.get(), bus_, recorder_.get(), &inbox_, &snapshots_, &board_, &targets_,
        [this](int64_t now_ns, bool summarize, int8_t new_state) {
          PublishStatus(now_ns, summarize, new_state);
        }});
    loop_->Run(stop_, realtime);
  } catch (const std::exception& e) {
    SetError(Cat("mechanics thread failed: ", e.what()));
    board_.set_state(session_status_t::kFaulted);
  } catch (...) {
    SetError("mechanics thread failed with a non-std exception");
    board_.set_state(session_status_t::kFaulted);
  }
  if (board_.state() == session_status_t::kFaulted) {
    try {
      PublishStatus(MonotonicNanos(), /*summarize=*/false);
    } catch (...) {
      // nothing more can be said
    }
  }
}

void Session::PublishStatus(int64_t now_ns, bool summarize, int8_t new_state) {
  session_status_t s = Status();
  s.header = bus::MakeHeader(config_.id, s.header.seq + 1);
  if (loop_ != nullptr) loop_->AddFigures(now_ns, summarize, &s);
  board_.Post(&s, new_state);
  if (loop_ != nullptr && loop_->Send(s)) return;
  // no loop, or none that got as far as its outbox: straight out, and into the record
  const std::string channel = bus::SessionChannel(bus::kStatusPrefix, config_.id);
  bus_->Publish(channel, s);
  if (recorder_ != nullptr) recorder_->Write(channel, s, s.header.utime);
}

}  // namespace viscera::session
