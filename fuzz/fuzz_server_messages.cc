// viscerad's whole receive path on any datagram: the I/O loop's bus (size limit, decode,
// exact-length check), the session manager's validation (header, token, replay guard, pose
// and frame checks, camera), answers and counts. The first input byte picks the channel: a
// request, a pose for a session that exists, or one for a session that does not.
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>

#include "bus/channels.h"
#include "server/io_loop.h"

namespace {

struct Server {
  Server() {
    viscera::server::ServerConfig config;
    config.lcm_url = "memq://";
    config.server_id = "fuzz";
    config.scene_dir = std::string(VISCERA_SOURCE_DIR) + "/scenes";
    config.max_sessions = 1;
    config.frame_rate_hz = -1.0;  // no render threads
    config.max_message_bytes = 64 * 1024;
    config.max_session_load = 0.0;  // no timing probe
    config.max_settle_s = 0.05;
    config.max_control_points = 64;
    loop = std::make_unique<viscera::server::IoLoop>(config);
  }
  std::unique_ptr<viscera::server::IoLoop> loop;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Server server;
  if (size < 1) return 0;
  static const std::string channels[] = {viscera::bus::kRequestChannel, "VISCERA_POSE_1",
                                         "VISCERA_POSE_77"};
  const std::string& channel = channels[data[0] % 3];
  server.loop->bus().PublishRaw(channel, data + 1, static_cast<int>(size - 1));
  server.loop->HandleWaiting();
  return 0;
}
