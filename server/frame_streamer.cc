#include "server/frame_streamer.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <exception>
#include <memory>
#include <utility>
#include <vector>

#include <viscera_proto/jpeg_frame_t.hpp>

#include "bus/channels.h"
#include "bus/header.h"
#include "common/check.h"
#include "common/clock.h"
#include "common/quantile.h"
#include "common/rate_window.h"
#include "render/laparoscope.h"
#include "server/frame_governor.h"
#include "server/frame_schedule.h"
#include "server/idle_priority.h"
#include "server/session_view.h"

namespace viscera::server {
namespace {

bool SamePose(const session::CameraPose& a, const session::CameraPose& b) {
  return a.set_by_client == b.set_by_client && a.eye == b.eye && a.target == b.target &&
         a.up == b.up && a.fov_deg == b.fov_deg;
}

// The frames of about the last second: achieved rate (frames sent, sampled every tick, so
// it falls to 0 when none come) and median costs for the status.
class FrameWindow {
 public:
  void Add(int64_t now_ns, const render::FrameTimings* timings) {
    frames_.push_back(
        {now_ns, timings != nullptr, timings != nullptr ? *timings : render::FrameTimings{}});
  }
  void Fill(int64_t now_ns, session::FrameStreamReport* report) {
    rate_.Add(now_ns, report->frames);
    report->achieved_rate_hz = rate_.Rate();
    while (!frames_.empty() && frames_.front().ns <= now_ns - 1'000'000'000) frames_.pop_front();
    skin_.clear();
    render_.clear();
    encode_.clear();
    for (const Entry& e : frames_) {
      if (!e.rendered) continue;  // a frame sent again unchanged cost nothing
      skin_.push_back(e.timings.skin_ms);
      render_.push_back(e.timings.render_ms);
      encode_.push_back(e.timings.encode_ms);
    }
    if (skin_.empty()) return;  // keep the last figures while nothing moves
    const int n_rendered = static_cast<int>(skin_.size());
    report->skin_ms = static_cast<float>(Quantile(skin_.data(), n_rendered, 0.5));
    report->render_ms = static_cast<float>(Quantile(render_.data(), n_rendered, 0.5));
    report->encode_ms = static_cast<float>(Quantile(encode_.data(), n_rendered, 0.5));
  }

 private:
  struct Entry {
    int64_t ns;
    bool rendered;
    render::FrameTimings timings;
  };
  std::deque<Entry> frames_;
  RateWindow rate_;
  std::vector<double> skin_, render_, encode_;  // reused
};

}  // namespace

FrameStreamer::FrameStreamer(session::Session* session, bus::LcmBus* bus, FrameStreamConfig config)
    : session_(session),
      bus_(bus),
      config_(std::move(config)),
      channel_(bus::SessionChannel(bus::kFramePrefix, session->config().id)) {
  VISCERA_DEMAND(session_ != nullptr && bus_ != nullptr && config_.rate_hz >= kMinFrameRateHz);
}

FrameStreamer::~FrameStreamer() { Stop(); }

void FrameStreamer::Start() {
  worker_.Start([this] { Run(); });
}

void FrameStreamer::RequestStop() { worker_.RequestStop(); }

void FrameStreamer::Stop() { worker_.Stop(); }

void FrameStreamer::ReportError(session::FrameStreamReport* report, const std::string& why) {
  report->error = why;
  ++report->error_serial;
  session_->ReportFrames(*report);
}

void FrameStreamer::Run() {
  LowerThisThreadsPriority();
  session::FrameStreamReport report;
  report.skin = config_.options.skin;
  report.rate_hz = config_.rate_hz;
  // An exception never crosses a thread: the session runs on without frames.
  try {
    render::FrameRenderer renderer(session_->model().params(),
                                   config_.options);  // its context is this thread's
    Loop(renderer, &report);
  } catch (const std::exception& e) {
    ReportError(&report, Cat("frames stopped: ", e.what()));
  } catch (...) {
    ReportError(&report, "frames stopped: a non-std exception");
  }
  report.achieved_rate_hz = 0.0;  // the stream has ended
  session_->ReportFrames(report);
  finished_ = true;
}

void FrameStreamer::Loop(render::FrameRenderer& renderer, session::FrameStreamReport* report) {
  // the governor lowers the rate, then the size, under load (FrameGovernor), when adaptive
  FrameGovernor governor;
  const int full_width = renderer.width(), full_height = renderer.height();
  int64_t period = std::llround(1e9 / config_.rate_hz);
  report->width = renderer.width();
  report->height = renderer.height();
  session_->ReportFrames(*report);

  viscera_proto::jpeg_frame_t frame;
  frame.width = renderer.width();
  frame.height = renderer.height();
  FrameWindow window;
  // What the last frame drawn showed. Values, not the snapshot itself: holding it would
  // keep a second snapshot buffer from the mechanics thread's pool while rendering.
  int64_t shown_step = -1;
  double shown_t = 0.0;
  int64_t shown_utime = 0;
  session::CameraPose shown_pose;
  render::Laparoscope framing;  // the scene as first seen, until a client sets the camera
  bool have_framing = false;
  std::string last_error;
  int64_t seq = 0;

  int64_t next = MonotonicNanos();
  const int64_t lease_ns = std::llround(config_.lease_s * 1e9);
  while (worker_.SleepUntil(next)) {
    const session::CameraPose pose = session_->camera();
    // nobody watches: no frame drawn or sent (a frame lease of 0 watches always)
    const bool watched = lease_ns <= 0 || session_->FramesWatched(MonotonicNanos(), lease_ns);
    std::shared_ptr<const session::Snapshot> snapshot =
        watched ? session_->LatestSnapshot() : nullptr;
    if (snapshot) {
      if (!have_framing) {
        framing = FirstFraming(session_->model().params(), snapshot->q, renderer.width(),
                               renderer.height());
        have_framing = true;
      }
      // nothing moved and the camera stayed: send the same picture again, it costs nothing
      const bool unchanged =
          shown_step == snapshot->step && SamePose(shown_pose, pose) && !frame.data.empty();
      bool ok = true;
      if (!unchanged) {
        try {
          renderer.SetDamage(snapshot->damaged);  // running the bowel's damaged parts
          renderer.Render(snapshot->q, snapshot->tools, SessionScope(pose, framing));
          const std::vector<uint8_t>& jpeg = renderer.Encode();
          frame.data.assign(jpeg.begin(), jpeg.end());
          frame.size = static_cast<int32_t>(frame.data.size());
          const render::FrameTimings& t = renderer.timings();
          frame.skin_ms = static_cast<float>(t.skin_ms);
          frame.render_ms = static_cast<float>(t.render_ms);
          frame.encode_ms = static_cast<float>(t.encode_ms);
          shown_step = snapshot->step;
          shown_t = snapshot->t;
          shown_utime = snapshot->wall_utime;
          shown_pose = pose;
          report->frame_bytes = frame.size;
          if (config_.adaptive &&
              governor.Update(FrameCost{t.skin_ms + t.render_ms + t.encode_ms, t.cpu_ms},
                              static_cast<double>(period) * 1e-6, session_->step_slack())) {
            const FrameLevel& level = governor.current();
            period = std::llround(1e9 / (config_.rate_hz * level.rate));
            // even sides: the JPEG's chroma subsampling takes them whole
            renderer.SetFrameSize(
                std::max(2, 2 * static_cast<int>(std::lround(full_width * level.scale / 2))),
                std::max(2, 2 * static_cast<int>(std::lround(full_height * level.scale / 2))));
            frame.width = report->width = renderer.width();
            frame.height = report->height = renderer.height();
            report->rate_hz = config_.rate_hz * level.rate;
          }
        } catch (const std::exception& e) {
          // e.g. a camera whose up vector lies along its view: say so once, keep trying
          ok = false;
          if (last_error != e.what()) ReportError(report, Cat("frame not rendered: ", e.what()));
          last_error = e.what();
        }
      } else {
        frame.skin_ms = frame.render_ms = frame.encode_ms = 0.0f;
      }
      snapshot.reset();  // back to the pool before the wait
      if (ok) {
        frame.header = bus::MakeHeader(session_->config().id, seq++);
        frame.step = shown_step;
        frame.sim_time = shown_t;
        frame.snapshot_utime = shown_utime;
        frame.dropped = report->dropped;
        bus_->Publish(channel_, frame);
        ++report->frames;
        window.Add(MonotonicNanos(), unchanged ? nullptr : &renderer.timings());
      }
    }

    const int64_t now = MonotonicNanos();
    report->dropped += AdvanceFrameSchedule(&next, now, period);
    window.Fill(now, report);
    session_->ReportFrames(*report);
  }
}

}  // namespace viscera::server
