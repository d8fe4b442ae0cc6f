// viscera create: places a session on a server and keeps its token.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>

#include "client/cli/commands.h"
#include "client/server_directory.h"
#include "client/token_store.h"

namespace viscera::client::cli {

using viscera_proto::session_reply_t;
using viscera_proto::session_request_t;

namespace {

struct CreateOptions {
  std::string scene;
  std::string scene_file;
  std::string server;
  std::string skin;
  double rate_hz = 0.0;
  double skeleton_rate_hz = 0.0;
  int width = 0, height = 0;
  double frame_rate_hz = 0.0;
  int jpeg_quality = 0;
  double listen_s = 1.2;  ///< heartbeats heard before placing (s)
  /// Seconds to wait for the create's answer once a server was heard: the server answers
  /// when the scene is built, at low priority, which takes seconds on a busy machine.
  double build_timeout_s = 60.0;
};

CreateOptions options;

}  // namespace

void SetUpCreate(CLI::App* cmd, Common* common) {
  (void)common;
  cmd->add_option("scene", options.scene, "Scene name in the server's scene directory");
  cmd->add_option("--scene-file", options.scene_file, "Send this scene file inline");
  cmd->add_option("--server", options.server,
                  "Server id (default: the least loaded server with room)");
  cmd->add_option("--listen", options.listen_s,
                  "Seconds to hear heartbeats before choosing a server")
      ->check(CLI::Range(0.05, 60.0))
      ->capture_default_str();
  cmd->add_option("--build-timeout", options.build_timeout_s,
                  "Seconds to wait for the heard server to build the scene and answer")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str();
  cmd->add_option("--rate", options.rate_hz,
                  "Mechanics rate (Hz; default: the scene's; servers cap it at their --max-rate, "
                  "1000 by default)")
      ->check(CLI::Range(1.0, 1000.0));
  cmd->add_option("--skeleton-rate", options.skeleton_rate_hz, "Skeleton state rate (Hz)");
  cmd->add_option("--skin", options.skin,
                  "Skin of the frames: parametric, implicit, convolution or hybrid");
  cmd->add_option("--width", options.width, "Frame width (pixels)");
  cmd->add_option("--height", options.height, "Frame height (pixels)");
  cmd->add_option("--frame-rate", options.frame_rate_hz,
                  "Frames per second (Hz; default: the server's, 25; < 0: no frames)");
  cmd->add_option("--jpeg-quality", options.jpeg_quality, "JPEG quality (1..100)")
      ->check(CLI::Range(1, 100));
}

int RunCreate(const std::string& url, const Common& c) {
  const CreateOptions& o = options;
  if (o.scene.empty() && o.scene_file.empty()) {
    std::fprintf(stderr,
                 "viscera: create needs a scene: a SCENE name from the server's scene directory "
                 "(viscera create cavity) or --scene-file FILE\n");
    return kLocalError;
  }
  if (!o.scene.empty() && !o.scene_file.empty()) {
    std::fprintf(stderr, "viscera: create takes a SCENE name or --scene-file, not both\n");
    return kLocalError;
  }
  SessionClient client(url, LoadAuth(c));
  std::string server_id = o.server;
  std::string placement;  // why this server, when the client chose it
  if (server_id.empty()) {
    // every server beats once a period: listen a little longer than one to hear them all
    const auto servers = client.HearServers(o.listen_s, c.timeout_s);
    if (servers.empty()) return NoServer(c, url, "(heartbeat)");
    const ServerInfo* best = PickServer(servers);
    if (best == nullptr) {
      std::fprintf(stderr, "viscera: every server is full (%s)\n", ServersSummary(servers).c_str());
      return kRefused;
    }
    server_id = best->server_id;
    placement = "least loaded of " + ServersSummary(servers);
  } else if (!client.FindServer(server_id, c.timeout_s)) {
    return NoServer(c, url, server_id.c_str());
  }
  session_request_t request = MakeRequest(session_request_t::kCreate, 0);
  request.server_id = server_id;
  if (!o.scene_file.empty()) {
    std::ifstream in(o.scene_file);
    if (!in.good()) {
      std::fprintf(stderr, "viscera: cannot read scene file '%s'\n", o.scene_file.c_str());
      return kLocalError;
    }
    request.scene_toml.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  } else {
    request.scene_name = o.scene;
  }
  request.rate_hz = o.rate_hz;
  request.skeleton_rate_hz = o.skeleton_rate_hz;
  request.skin = o.skin;
  request.frame_width = o.width;
  request.frame_height = o.height;
  request.frame_rate_hz = o.frame_rate_hz;
  request.jpeg_quality = o.jpeg_quality;
  const double wait_s = std::max(c.timeout_s, o.build_timeout_s);
  const auto replies = client.Request(request, wait_s);
  if (replies.empty()) {
    std::fprintf(
        stderr,
        "viscera: server '%s' did not answer the create request within %g s (it was heard: "
        "has it stopped, or is its scene build still running? --build-timeout)\n",
        server_id.c_str(), wait_s);
    return kNoServer;
  }
  if (replies.front().result != session_reply_t::kOk) {
    session_reply_t named = replies.front();
    // the server knows an inline scene as "<scene dir>/<inline>": name the user's file
    for (size_t at;
         !o.scene_file.empty() && (at = named.message.find("<inline>")) != std::string::npos;) {
      const size_t dir =
          named.message.rfind(' ', at) == std::string::npos ? 0 : named.message.rfind(' ', at) + 1;
      named.message.replace(dir, at + 8 - dir, o.scene_file);
    }
    return ReplyError(named, 0);
  }
  const session_reply_t& reply = replies.front();
  const int64_t id = reply.header.session_id;
  TokenStore store(c.sessions_file);
  store.Put(id, {reply.header.token, reply.server_id});
  if (!reply.message.empty())
    std::fprintf(stderr, "viscera: scene warnings: %s\n", reply.message.c_str());
  if (c.json) {
    Json j = {{"session", id},
              {"server_id", reply.server_id},
              {"placement", placement.empty() ? "--server" : placement},
              {"token", ToHex(reply.header.token)},
              {"scene", o.scene.empty() ? "<inline>" : o.scene},
              {"warnings", reply.message}};
    if (reply.num_sessions > 0) {
      j["rate_hz"] = reply.sessions[0].rate_hz;
      j["tools"] = reply.sessions[0].tool_names;
    }
    std::cout << j.dump(2) << "\n";
  } else {
    std::printf("session %lld created on %s (%s; token saved in %s)\n", static_cast<long long>(id),
                reply.server_id.c_str(),
                placement.empty() ? "named by --server" : placement.c_str(),
                c.sessions_file.c_str());
  }
  return 0;
}

}  // namespace viscera::client::cli
