#include "client/frame_commands.h"

#include <signal.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <optional>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "bus/lcm_bus.h"
#include "client/frame_receiver.h"
#include "client/jpeg_header.h"
#include "client/session_client.h"
#include "client/stop_signals.h"
#include "common/check.h"

namespace viscera::client {
namespace {

using Clock = std::chrono::steady_clock;
using viscera_proto::jpeg_frame_t;

// A frame message at most: a 4096 x 4096 JPEG at quality 100 is about 8 MB.
constexpr int kMaxFrameMessageBytes = 16 << 20;

void PrintSummary(const FrameListenOptions& o, const FrameStreamStats& s,
                  const std::string& where) {
  const double total = static_cast<double>(s.received + s.lost);
  const double loss_pct = total > 0 ? 100.0 * static_cast<double>(s.lost) / total : 0.0;
  const double mean_kb = s.received > 0 ? static_cast<double>(s.bytes) / s.received / 1024.0 : 0.0;
  if (o.json) {
    nlohmann::ordered_json j = {{"session", o.session_id},
                                {"frames", s.received},
                                {"lost", s.lost},
                                {"loss_percent", loss_pct},
                                {"server_dropped", s.server_dropped},
                                {"seconds", s.seconds},
                                {"rate_hz", s.rate_hz},
                                {"mean_kb", mean_kb},
                                {"age_p50_ms", s.age_p50_ms},
                                {"age_p99_ms", s.age_p99_ms},
                                {"output", where}};
    std::cout << j.dump(2) << "\n";
    return;
  }
  std::printf("%lld frames in %.2f s (%.1f fps) -> %s\n", static_cast<long long>(s.received),
              s.seconds, s.rate_hz, where.c_str());
  std::printf(
      "lost on the way %lld (%.2f %%), dropped by the server's renderer %lld, "
      "mean %.1f kB, age p50 %.1f ms p99 %.1f ms\n",
      static_cast<long long>(s.lost), loss_pct, static_cast<long long>(s.server_dropped), mean_kb,
      s.age_p50_ms, s.age_p99_ms);
}

// Pumps the session's frames into `on_frame` until the count or duration is reached, a
// signal comes, `on_frame` returns false, or no frame comes for timeout_s. Prints the
// summary.
int Listen(const FrameListenOptions& o, const std::string& where,
           const std::function<bool(const jpeg_frame_t&)>& on_frame) {
  const StopSignals signals;
  bus::LcmBus bus(WithReceiveBuffer(o.url));
  bus.SetAuth(o.auth);
  bus.SetMaxMessageSize(kMaxFrameMessageBytes);  // larger ones are dropped before decoding
  bool failed = false;
  FrameReceiver receiver(&bus, o.session_id, [&](const jpeg_frame_t& frame) {
    if (!failed && !on_frame(frame)) failed = true;
  });

  const auto start = Clock::now();
  auto last_frame = start;
  int64_t seen = 0;
  while (!failed && !signals.Received()) {
    bus.Pump(50);
    const auto now = Clock::now();
    if (receiver.received() > seen) {
      seen = receiver.received();
      last_frame = now;
    }
    if (o.count > 0 && seen >= o.count) break;
    if (o.seconds > 0 && now - start >= std::chrono::duration<double>(o.seconds)) break;
    if (now - last_frame >= std::chrono::duration<double>(o.timeout_s)) {
      if (seen > 0) {
        std::fprintf(stderr, "viscera: the stream of session %lld stopped (no frame for %g s)\n",
                     static_cast<long long>(o.session_id), o.timeout_s);
        break;
      }
      std::fprintf(stderr,
                   "viscera: no frame of session %lld on %s within %g s (does the session exist "
                   "and stream frames, i.e. frame rate > 0?%s)\n",
                   static_cast<long long>(o.session_id), o.url.c_str(), o.timeout_s,
                   o.auth != nullptr ? "" : " does the server need --key-file?");
      return kFramesNone;
    }
  }
  if (receiver.rejected() > 0) {
    std::fprintf(stderr, "viscera: %lld frame(s) rejected: %s\n",
                 static_cast<long long>(receiver.rejected()), receiver.last_rejection().c_str());
  }
  if (failed) return kFramesLocalError;
  PrintSummary(o, receiver.stats(), where);
  return kFramesOk;
}

}  // namespace

int SaveFrames(const FrameListenOptions& options, const std::string& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) {
    std::fprintf(stderr, "viscera: cannot create %s: %s\n", dir.c_str(), error.message().c_str());
    return kFramesLocalError;
  }
  int64_t index = 0;
  return Listen(options, dir, [&](const jpeg_frame_t& frame) {
    char name[32];
    std::snprintf(name, sizeof(name), "/frame_%06lld.jpg", static_cast<long long>(index++));
    std::ofstream out(dir + name, std::ios::binary);
    out.write(reinterpret_cast<const char*>(frame.data.data()),
              static_cast<std::streamsize>(frame.data.size()));
    if (!out.good()) {
      std::fprintf(stderr, "viscera: cannot write %s%s\n", dir.c_str(), name);
      return false;
    }
    return true;
  });
}

namespace {

// The session's configured frame rate (Hz) from its status, or 0 when no server answers.
double SessionFrameRate(const FrameListenOptions& o) {
  SessionClient client(o.url, o.auth);
  const auto replies = client.Request(
      MakeRequest(viscera_proto::session_request_t::kStatus, o.session_id), o.timeout_s);
  for (const viscera_proto::session_reply_t& r : replies) {
    if (r.result == viscera_proto::session_reply_t::kOk && r.num_sessions == 1) {
      return r.sessions[0].frame_rate_hz;
    }
  }
  return 0.0;
}

}  // namespace

int RecordVideo(const FrameListenOptions& options, const std::string& file, double fps) {
  const std::string ext = std::filesystem::path(file).extension().string();
  int fourcc = 0;
  if (ext == ".mp4") {
    fourcc = cv::VideoWriter::fourcc('m', 'p', '4', 'v');
  } else if (ext == ".avi") {
    fourcc = cv::VideoWriter::fourcc('M', 'J', 'P', 'G');
  } else {
    std::fprintf(stderr, "viscera: record writes .mp4 or .avi, not '%s'\n", file.c_str());
    return kFramesLocalError;
  }
  if (fps <= 0.0) {
    fps = SessionFrameRate(options);
    if (fps <= 0.0) {
      std::fprintf(stderr,
                   "viscera: session %lld streams no frames (or no server answered); "
                   "--fps sets the video's rate\n",
                   static_cast<long long>(options.session_id));
      return kFramesNone;
    }
  }
  cv::VideoWriter writer;
  cv::Mat previous;
  int64_t previous_seq = -1, previous_dropped = 0, filled = 0, undecodable = 0;
  const int code = Listen(options, file, [&](const jpeg_frame_t& frame) {
    // ticks without a picture (lost on the way, dropped by the renderer) repeat the last one,
    // at most a second's worth at a time (a stalled server, not a frozen video)
    const int64_t missing = previous_seq < 0
                                ? 0
                                : (frame.header.seq - previous_seq - 1) +
                                      std::max<int64_t>(0, frame.dropped - previous_dropped);
    previous_seq = frame.header.seq;
    previous_dropped = frame.dropped;
    if (writer.isOpened()) {
      for (int64_t k = 0; k < std::min<int64_t>(missing, static_cast<int64_t>(fps));
           ++k, ++filled) {
        writer.write(previous);
      }
    }
    // the header first: a frame claiming 30000 x 30000 pixels is skipped, not decoded
    if (!JpegProblem(frame.data.data(), frame.data.size(), frame.width, frame.height).empty()) {
      ++undecodable;
      return true;
    }
    const cv::Mat image = cv::imdecode(frame.data, cv::IMREAD_COLOR);
    if (image.empty() || image.cols != frame.width || image.rows != frame.height) {
      ++undecodable;  // a damaged frame is skipped, the video goes on
      return true;
    }
    previous = image;
    if (!writer.isOpened()) {
      // the size of the first frame is the video's (a session's frames never change size)
      if (!writer.open(file, cv::CAP_FFMPEG, fourcc, fps, image.size(), true)) {
        std::fprintf(stderr, "viscera: OpenCV cannot write %s (FFmpeg backend missing?)\n",
                     file.c_str());
        return false;
      }
    }
    writer.write(image);
    return true;
  });
  writer.release();  // writes the container's index: a video cut by Ctrl-C still plays
  if (filled > 0) {
    std::fprintf(stderr,
                 "viscera: %lld frame(s) missing from the stream were filled with the one before\n",
                 static_cast<long long>(filled));
  }
  if (undecodable > 0) {
    std::fprintf(stderr, "viscera: %lld frame(s) did not decode and were skipped\n",
                 static_cast<long long>(undecodable));
  }
  return code;
}

}  // namespace viscera::client
