// viscera frames, record, view: listen to one session's frame stream.
#include <algorithm>
#include <cstdio>
#include <optional>
#include <vector>

#include "client/cli/commands.h"
#include "client/frame_commands.h"
#include "client/keep_alive.h"

namespace viscera::client::cli {

using viscera_proto::session_request_t;

namespace {

// one command runs per process: the three share what they parse into
FrameListenOptions listen_options;
std::string frames_dir, record_file, view_address = "127.0.0.1:8080", view_scene,
                                     view_scene_dir = "scenes";
double record_fps = 0.0;

void AddListenOptions(CLI::App* cmd) {
  cmd->add_option("id", listen_options.session_id, "Session id")->required();
  cmd->add_option("--count", listen_options.count, "Stop after N frames")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--seconds", listen_options.seconds, "Stop after S seconds")
      ->check(CLI::NonNegativeNumber);
}

// Sets up `listen_options` and keeps the session (and, with `watch_frames`, its frames) alive while
// `run` listens.
int ListenWhileKeepingAlive(const std::string& url, const Common& c, bool watch_frames,
                            const std::function<int()>& run) {
  listen_options.url = url;
  listen_options.auth = LoadAuth(c);
  listen_options.timeout_s = std::max(c.timeout_s, 5.0);  // the first frame may need a scene built
  listen_options.json = c.json;
  // a viewer with the session's token keeps the session alive while it watches
  SessionClient keeper(url, listen_options.auth);
  const std::vector<uint8_t> token = TokenFor(c, listen_options.session_id, nullptr);
  if (token.empty()) {
    std::fprintf(stderr,
                 "viscera: no token for session %lld here: watching without renewing its lease\n",
                 static_cast<long long>(listen_options.session_id));
  }
  double lease_s = 0.0;
  if (!token.empty()) {
    const auto replies = keeper.Request(
        MakeRequest(session_request_t::kStatus, listen_options.session_id), c.timeout_s);
    if (!replies.empty() && replies.front().num_sessions > 0)
      lease_s = replies.front().sessions[0].lease_s;
  }
  KeepAlive keep_alive(&keeper, listen_options.session_id, token, KeepAlivePeriod(lease_s));
  // frames and record take every frame: they renew the frame lease (view does while its page
  // shows server frames)
  std::optional<KeepAlive> watch;
  if (watch_frames) {
    watch.emplace(&keeper, listen_options.session_id, token, kFrameWatchPeriodS,
                  session_request_t::kWatchFrames);
  }
  return run();
}

}  // namespace

void SetUpFrames(CLI::App* cmd, Common* common) {
  (void)common;
  AddListenOptions(cmd);
  cmd->add_option("--out", frames_dir, "Directory for frame_000000.jpg, ...")->required();
}

int RunFrames(const std::string& url, const Common& c) {
  return ListenWhileKeepingAlive(url, c, /*watch_frames=*/true,
                                 [] { return SaveFrames(listen_options, frames_dir); });
}

void SetUpRecord(CLI::App* cmd, Common* common) {
  (void)common;
  AddListenOptions(cmd);
  cmd->add_option("--out", record_file, "Video file (.mp4: MPEG-4 part 2, .avi: MJPEG)")
      ->required();
  cmd->add_option("--fps", record_fps,
                  "Frames per second of the video (default: the session's frame rate)")
      ->check(CLI::Range(1.0, 240.0));
}

int RunRecord(const std::string& url, const Common& c) {
  return ListenWhileKeepingAlive(url, c, /*watch_frames=*/true, [] {
    return RecordVideo(listen_options, record_file, record_fps);
  });
}

void SetUpView(CLI::App* cmd, Common* common) {
  (void)common;
  AddListenOptions(cmd);
  cmd->add_option("--http", view_address, "Address to serve on, HOST:PORT (keep it on loopback)")
      ->capture_default_str();
  cmd->add_option(
      "--scene", view_scene,
      "The session's scene file, for the page to draw from (default: SCENE-DIR/<its scene>.toml)");
  cmd->add_option("--scene-dir", view_scene_dir, "Where the session's named scene is looked for")
      ->capture_default_str();
}

int RunView(const std::string& url, const Common& c) {
  return ListenWhileKeepingAlive(url, c, /*watch_frames=*/false, [] {
    return ViewOverHttp(listen_options, view_address, view_scene, view_scene_dir);
  });
}

}  // namespace viscera::client::cli
