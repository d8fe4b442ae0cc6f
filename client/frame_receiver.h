#pragma once
/// FrameReceiver: the client side of a session's frame stream (VISCERA_FRAME_<id>). It
/// hands each frame on and measures the stream: frames lost on the way (gaps in the
/// frame sequence), frames the server dropped (its renderer was busy), rate and age.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <viscera_proto/jpeg_frame_t.hpp>

#include "bus/lcm_bus.h"

namespace viscera::client {

/// Receive buffer asked for frame streams: a 640x480 frame is about 25 fragments of 1.4 kB
/// (LCM 1.3.1), and a whole second of 25 Hz frames fits in 2 MB (docs/frame-streams.md).
inline constexpr int kFrameReceiveBuffer = 2 * 1024 * 1024;

/// `url` with `recv_buf_size=bytes` added, when it is a udpm:// URL that sets none; any
/// other URL unchanged. LCM 1.3.1 loses a whole fragmented message when the kernel's
/// receive buffer overflows, so frame clients ask for a large one.
std::string WithReceiveBuffer(const std::string& url, int bytes = kFrameReceiveBuffer);

struct FrameStreamStats {
  int64_t received = 0;        ///< frames handed on
  int64_t lost = 0;            ///< missing sequence numbers between received frames
  int64_t server_dropped = 0;  ///< skipped by the server's renderer while these arrived
  int64_t bytes = 0;           ///< JPEG bytes received
  double seconds = 0.0;        ///< from the first frame received to the last
  double rate_hz = 0.0;        ///< (received - 1) / seconds
  /// receive time - snapshot time, median and 99th percentile over the last kAgeWindow frames
  double age_p50_ms = 0.0;
  double age_p99_ms = 0.0;
};

class FrameReceiver {
 public:
  /// Frames whose age the percentiles cover (the most recent ones: a viewer runs for days).
  static constexpr size_t kAgeWindow = 10000;

  using Handler = std::function<void(const viscera_proto::jpeg_frame_t& frame)>;

  /// Subscribes to session `session_id`'s frames on `bus`. Frames of another protocol
  /// version or session, without bytes or size, or with a sequence number older than the
  /// last one are counted as rejected and not handed on.
  /// @pre bus outlives the receiver; the bus's owner thread pumps it.
  FrameReceiver(bus::LcmBus* bus, int64_t session_id, Handler handler);

  FrameStreamStats stats() const;
  int64_t received() const { return received_; }
  int64_t rejected() const { return rejected_; }
  /// Why the last frame was rejected ("" if none was).
  const std::string& last_rejection() const { return last_rejection_; }

 private:
  void OnFrame(const viscera_proto::jpeg_frame_t& frame, int64_t recv_utime);

  Handler handler_;
  int64_t received_ = 0;
  int64_t rejected_ = 0;
  std::string last_rejection_;
  int64_t last_seq_ = -1;
  int64_t lost_ = 0;
  int64_t first_dropped_ = -1, last_dropped_ = 0;
  int64_t bytes_ = 0;
  int64_t first_utime_ = 0, last_utime_ = 0;
  std::vector<double> ages_ms_;  // a ring of the last kAgeWindow ages
  size_t next_age_ = 0;
  int64_t session_id_;
};

}  // namespace viscera::client
