// viscera camera: sets a session's laparoscope camera.
#include <vector>

#include "client/cli/commands.h"

namespace viscera::client::cli {

using viscera_proto::session_request_t;

namespace {

struct CameraOptions {
  int64_t id = 0;
  std::vector<double> eye{0.0, -0.3, 0.3}, target{0.0, 0.0, 0.0}, up{0.0, 0.0, 1.0};
  double fov = 60.0;
};

CameraOptions options;

}  // namespace

void SetUpCamera(CLI::App* cmd, Common* common) {
  cmd->add_option("id", options.id, "Session id")->required();
  cmd->add_option("--eye", options.eye, "Eye x y z (m)")->expected(3)->required();
  cmd->add_option("--target", options.target, "Look-at point x y z (m)")->expected(3)->required();
  cmd->add_option("--up", options.up, "Up vector")->expected(3);
  cmd->add_option("--fov", options.fov, "Vertical field of view (degrees)");
  AddTokenOptions(cmd, common);
}

int RunCamera(const std::string& url, const Common& c) {
  const CameraOptions& o = options;
  return RunSessionRequest(url, c, session_request_t::kCamera, o.id, [&](session_request_t* r) {
    for (int a = 0; a < 3; ++a) {
      r->camera_eye[a] = o.eye[static_cast<size_t>(a)];
      r->camera_target[a] = o.target[static_cast<size_t>(a)];
      r->camera_up[a] = o.up[static_cast<size_t>(a)];
    }
    r->camera_fov_deg = o.fov;
  });
}

}  // namespace viscera::client::cli
