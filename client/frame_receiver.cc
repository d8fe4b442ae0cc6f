#include "client/frame_receiver.h"

#include <utility>

#include "bus/channels.h"
#include "common/check.h"
#include "common/quantile.h"

namespace viscera::client {

std::string WithReceiveBuffer(const std::string& url, int bytes) {
  if (url.rfind("udpm://", 0) != 0 || url.find("recv_buf_size=") != std::string::npos) return url;
  return Cat(url, url.find('?') == std::string::npos ? "?" : "&", "recv_buf_size=", bytes);
}

FrameReceiver::FrameReceiver(bus::LcmBus* bus, int64_t session_id, Handler handler)
    : handler_(std::move(handler)) {
  VISCERA_DEMAND(bus != nullptr && handler_);
  bus->Subscribe<viscera_proto::jpeg_frame_t>(
      bus::SessionChannel(bus::kFramePrefix, session_id),
      [this](const viscera_proto::jpeg_frame_t& frame, int64_t recv_utime) { OnFrame(frame, recv_utime); });
}

void FrameReceiver::OnFrame(const viscera_proto::jpeg_frame_t& frame, int64_t recv_utime) {
  if (frame.size <= 0 || frame.width <= 0 || frame.height <= 0 || frame.header.seq < 0) {
    ++rejected_;
    last_rejection_ = Cat("frame ", frame.header.seq, " of ", frame.size, " bytes, ", frame.width,
                          "x", frame.height, " pixels");
    return;
  }
  // a gap in the sequence is a frame LCM lost on the way (all fragments or one)
  if (last_seq_ >= 0 && frame.header.seq > last_seq_ + 1) lost_ += frame.header.seq - last_seq_ - 1;
  if (frame.header.seq > last_seq_) last_seq_ = frame.header.seq;
  if (first_dropped_ < 0) first_dropped_ = frame.dropped;
  last_dropped_ = frame.dropped;
  if (received_ == 0) first_utime_ = recv_utime;
  last_utime_ = recv_utime;
  ++received_;
  bytes_ += frame.size;
  ages_ms_.push_back(static_cast<double>(recv_utime - frame.snapshot_utime) * 1e-3);
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
