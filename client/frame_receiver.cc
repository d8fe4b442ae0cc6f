#include "client/frame_receiver.h"

#include <utility>

#include "bus/channels.h"
#include "bus/header.h"
#include "common/check.h"
#include "common/quantile.h"

namespace viscera::client {

std::string WithReceiveBuffer(const std::string& url, int bytes) {
  if (url.rfind("udpm://", 0) != 0 || url.find("recv_buf_size=") != std::string::npos) return url;
  return Cat(url, url.find('?') == std::string::npos ? "?" : "&", "recv_buf_size=", bytes);
}

FrameReceiver::FrameReceiver(bus::LcmBus* bus, int64_t session_id, Handler handler)
    : handler_(std::move(handler)), session_id_(session_id) {
  VISCERA_DEMAND(bus != nullptr && handler_);
  bus->Subscribe<viscera_proto::jpeg_frame_t>(
      bus::SessionChannel(bus::kFramePrefix, session_id),
      [this](const viscera_proto::jpeg_frame_t& frame, int64_t recv_utime) {
        OnFrame(frame, recv_utime);
      });
}

void FrameReceiver::OnFrame(const viscera_proto::jpeg_frame_t& frame, int64_t recv_utime) {
  std::string problem = bus::HeaderProblem(frame.header);
  if (problem.empty() && frame.header.session_id != session_id_) {
    problem = Cat("session ", frame.header.session_id, " on the channel of ", session_id_);
  }
  if (problem.empty() && (frame.size <= 0 || frame.width <= 0 || frame.height <= 0)) {
    problem = Cat("frame of ", frame.size, " bytes, ", frame.width, "x", frame.height, " pixels");
  }
  if (problem.empty() && frame.header.seq <= last_seq_) {
    problem = Cat("frame ", frame.header.seq, " after frame ", last_seq_);  // stale or replayed
  }
  if (!problem.empty()) {
    ++rejected_;
    last_rejection_ = problem;
    return;
  }
  // a gap in the sequence is a frame LCM lost on the way (all fragments or one)
  if (last_seq_ >= 0) lost_ += frame.header.seq - last_seq_ - 1;
  last_seq_ = frame.header.seq;
  if (first_dropped_ < 0) first_dropped_ = frame.dropped;
  last_dropped_ = frame.dropped;
  if (received_ == 0) first_utime_ = recv_utime;
  last_utime_ = recv_utime;
  ++received_;
  bytes_ += frame.size;
  // in double: a frame's time is the sender's word, and INT64_MIN overflows the integers'
  // difference
  const double age_ms =
      (static_cast<double>(recv_utime) - static_cast<double>(frame.snapshot_utime)) * 1e-3;
  if (ages_ms_.size() < kAgeWindow) {
    ages_ms_.push_back(age_ms);
  } else {
    ages_ms_[next_age_] = age_ms;
    next_age_ = (next_age_ + 1) % kAgeWindow;
  }
  handler_(frame);
}

FrameStreamStats FrameReceiver::stats() const {
  FrameStreamStats s;
  s.received = received_;
  s.lost = lost_;
  s.server_dropped = first_dropped_ >= 0 ? last_dropped_ - first_dropped_ : 0;
  s.bytes = bytes_;
  s.seconds = static_cast<double>(last_utime_ - first_utime_) * 1e-6;
  s.rate_hz = s.seconds > 0.0 ? static_cast<double>(received_ - 1) / s.seconds : 0.0;
  s.age_p50_ms = Quantile(ages_ms_, 0.5);
  s.age_p99_ms = Quantile(ages_ms_, 0.99);
  return s;
}

}  // namespace viscera::client
