// mjpeg_feeder: an MjpegServer on 127.0.0.1 (ephemeral port) fed a moving disc at 25 Hz,
// so that a browser can be tested against the viewer without the rest of viscera
// (tests/e2e/viewer_chromium_test.sh).
// Usage: mjpeg_feeder [--seconds S]   (default 30; SIGTERM or SIGINT end it sooner)
// Prints "port N" on stdout once serving, and the server's stats on stderr at the end.
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "client/mjpeg_server.h"
#include "common/check.h"

namespace {

volatile std::sig_atomic_t g_stop = 0;  // set by SIGTERM / SIGINT; the only global, for the handler

// Frame `i` (at 25 Hz): a disc going round once every 2 s, and the frame number.
std::vector<uint8_t> Picture(int i) {
  cv::Mat image(240, 320, CV_8UC3, cv::Scalar(40, 25, 20));
  const double angle = 2.0 * M_PI * i / 50.0;
  const cv::Point centre(160 + static_cast<int>(100 * std::cos(angle)),
                         120 + static_cast<int>(70 * std::sin(angle)));
  cv::circle(image, centre, 28, cv::Scalar(90, 150, 235), cv::FILLED, cv::LINE_AA);
  cv::putText(image, std::to_string(i), cv::Point(8, 228), cv::FONT_HERSHEY_SIMPLEX, 0.6,
              cv::Scalar(200, 200, 200), 1, cv::LINE_AA);
  std::vector<uint8_t> jpeg;
  VISCERA_DEMAND(cv::imencode(".jpg", image, jpeg));
  return jpeg;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace std::chrono_literals;
  double seconds = 30.0;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      viscera::ThrowUnless(arg == "--seconds" && i + 1 < argc, "unknown argument '", arg,
                           "' (usage: mjpeg_feeder [--seconds S])");
      seconds = std::stod(argv[++i]);
    }
  } catch (const std::exception& e) {  // InputError, or stod's invalid_argument
    std::fprintf(stderr, "mjpeg_feeder: %s\n", e.what());
    return 2;
  }
  std::signal(SIGTERM, [](int) { g_stop = 1; });
  std::signal(SIGINT, [](int) { g_stop = 1; });

  viscera::client::MjpegServer server("127.0.0.1", 0, "mjpeg feeder");
  std::printf("port %d\n", server.port());
  std::fflush(stdout);

  const auto start = std::chrono::steady_clock::now();
  const auto end = start + std::chrono::duration<double>(seconds);
  for (int i = 0; !g_stop && std::chrono::steady_clock::now() < end; ++i) {
    server.PostFrame(Picture(i));
    std::this_thread::sleep_until(start + (i + 1) * 40ms);  // 25 Hz, without drift
  }
  const viscera::client::MjpegServerStats stats = server.stats();
  std::fprintf(stderr, "mjpeg_feeder: %s", viscera::client::StatsToJson(stats).c_str());
  return 0;
}
