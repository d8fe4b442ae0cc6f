#include <chrono>
#include <cstdio>
#include <map>
#include <optional>

#include <viscera_proto/force_feedback_t.hpp>
#include <viscera_proto/skeleton_state_t.hpp>
#include <viscera_proto/tool_pose_t.hpp>

#include "bus/channels.h"
#include "bus/header.h"
#include "bus/lcm_bus.h"
#include "client/frame_commands.h"
#include "client/frame_receiver.h"
#include "client/keep_alive.h"
#include "client/mjpeg_server.h"
#include "client/session_client.h"
#include "client/stop_signals.h"
#include "client/view_scene.h"
#include "common/check.h"

namespace viscera::client {
namespace {

using Clock = std::chrono::steady_clock;

// From the session's status: its scene's name and its frame size (the page draws at the
// server's size; 640x480 when the session has no frames). False when no server answers.
bool SessionScene(const FrameListenOptions& o, std::string* scene, int* width, int* height) {
  SessionClient client(o.url, o.auth);
  const auto replies = client.Request(
      MakeRequest(viscera_proto::session_request_t::kStatus, o.session_id), o.timeout_s);
  for (const viscera_proto::session_reply_t& r : replies) {
    if (r.result != viscera_proto::session_reply_t::kOk || r.num_sessions != 1) continue;
    *scene = r.sessions[0].scene;
    if (r.sessions[0].frame_width > 0 && r.sessions[0].frame_height > 0) {
      *width = r.sessions[0].frame_width;
      *height = r.sessions[0].frame_height;
    }
    return true;
  }
  return false;
}

// The scene the page draws, or none (said why): the file given, else the status's scene name
// in scene_dir.
std::optional<mechanics::ModelParams> ViewedScene(const FrameListenOptions& o, std::string file,
                                                  const std::string& scene_dir, int* width,
                                                  int* height) {
  std::string name;
  const bool answered = SessionScene(o, &name, width, height);
  if (file.empty()) {
    if (!answered) {
      std::fprintf(stderr,
                   "viscera: no status of session %lld: the page shows server frames only\n",
                   static_cast<long long>(o.session_id));
      return std::nullopt;
    }
    if (name.empty() || name.front() == '<' || name.find('/') != std::string::npos) {
      std::fprintf(stderr,
                   "viscera: session %lld runs scene '%s': --scene FILE lets the page draw it\n",
                   static_cast<long long>(o.session_id), name.c_str());
      return std::nullopt;
    }
    file = Cat(scene_dir, "/", name, ".toml");
  }
  try {
    return LoadSceneGeometry(file);
  } catch (const InputError& e) {
    std::fprintf(stderr, "viscera: the page shows server frames only: %s\n", e.what());
    return std::nullopt;
  }
}

// A message of this session, current protocol: else why not.
std::string Problem(const viscera_proto::header_t& header, int64_t session_id) {
  std::string problem = bus::HeaderProblem(header);
  if (problem.empty() && header.session_id != session_id) {
    problem = Cat("session ", header.session_id, " on the channel of ", session_id);
  }
  return problem;
}

}  // namespace

int ViewOverHttp(const FrameListenOptions& options, const std::string& host_port,
                 const std::string& scene_file, const std::string& scene_dir) {
  std::string host;
  int port = 0;
  ParseHostPort(host_port, &host, &port);
  int width = 640, height = 480;
  const std::optional<mechanics::ModelParams> scene =
      ViewedScene(options, scene_file, scene_dir, &width, &height);

  const StopSignals signals;  // before the server's threads start: they inherit the mask
  MjpegServer server(host, port, Cat("viscera session ", options.session_id), scene.has_value());
  std::fprintf(stderr, "viscera: session %lld on http://%s:%d/ (%s; Ctrl-C stops)\n",
               static_cast<long long>(options.session_id), host.c_str(), server.port(),
               scene ? "drawn in the page from its skeleton, server frames at ?video=server"
                     : "server frames");

  bus::LcmBus bus(WithReceiveBuffer(options.url));
  bus.SetAuth(options.auth);
  FrameReceiver frames(&bus, options.session_id, [&](const viscera_proto::jpeg_frame_t& frame) {
    server.PostFrame(frame.data);
    const double now_us = static_cast<double>(bus::WallMicros());
    server.NoteFrame(frame.step, (now_us - static_cast<double>(frame.snapshot_utime)) * 1e-3);
  });

  // the page's stream: skeleton states, with the tools as the bus shows them
  int64_t skeletons = 0, refused = 0;
  std::string last_refusal;
  std::vector<ViewedTool> tools(scene ? scene->tools.size() : 0);
  bool scene_sent = false, scene_dropped = false;
  // a camera a client sets (viscera camera): taken once the server's reply accepts it
  std::string camera;
  std::map<int64_t, viscera_proto::session_request_t> camera_asked;  // by request_id
  if (scene) {
    bus.Subscribe<viscera_proto::session_request_t>(
        bus::kRequestChannel, [&](const viscera_proto::session_request_t& r, int64_t) {
          if (r.command != viscera_proto::session_request_t::kCamera ||
              r.header.session_id != options.session_id) {
            return;
          }
          if (camera_asked.size() >= 16) camera_asked.erase(camera_asked.begin());
          camera_asked[r.request_id] = r;
        });
    bus.Subscribe<viscera_proto::session_reply_t>(
        bus::kReplyChannel, [&](const viscera_proto::session_reply_t& r, int64_t) {
          const auto asked = camera_asked.find(r.request_id);
          if (asked == camera_asked.end()) return;
          if (r.result == viscera_proto::session_reply_t::kOk) {
            try {
              camera = LookAtCameraJson(asked->second, width, height);
            } catch (const InputError& e) {
              std::fprintf(stderr, "viscera: the page keeps its camera: %s\n", e.what());
            }
          }
          camera_asked.erase(asked);
        });
    bus.Subscribe<viscera_proto::force_feedback_t>(
        bus::SessionChannel(bus::kForcePrefix, options.session_id),
        [&](const viscera_proto::force_feedback_t& f, int64_t) {
          if (!Problem(f.header, options.session_id).empty() || f.tool < 0 ||
              f.tool >= static_cast<int>(tools.size())) {
            return;
          }
          ViewedTool& t = tools[static_cast<size_t>(f.tool)];
          t.seen = t.seen || f.pose_seq >= 0;
          for (int a = 0; a < 3; ++a) t.tip[a] = f.tip[a];
        });
    bus.Subscribe<viscera_proto::tool_pose_t>(
        bus::SessionChannel(bus::kPosePrefix, options.session_id),
        [&](const viscera_proto::tool_pose_t& p, int64_t) {
          if (p.tool < 0 || p.tool >= static_cast<int>(tools.size())) return;
          const double norm2 =
              p.orientation[0] * p.orientation[0] + p.orientation[1] * p.orientation[1] +
              p.orientation[2] * p.orientation[2] + p.orientation[3] * p.orientation[3];
          if (!(norm2 > 0.25 && norm2 < 4.0) || !(p.jaw >= 0.0 && p.jaw <= 1.0))
            return;  // as the server
          ViewedTool& t = tools[static_cast<size_t>(p.tool)];
          for (int a = 0; a < 4; ++a) t.orientation[a] = p.orientation[a];
          t.jaw = p.jaw;
        });
    bus.Subscribe<viscera_proto::skeleton_state_t>(
        bus::SessionChannel(bus::kSkeletonPrefix, options.session_id),
        [&](const viscera_proto::skeleton_state_t& s, int64_t) {
          const auto refuse = [&](const std::string& problem) {
            if (refused++ == 0)
              std::fprintf(stderr, "viscera: skeleton state refused: %s\n", problem.c_str());
            last_refusal = problem;
          };
          if (const std::string problem = Problem(s.header, options.session_id); !problem.empty()) {
            refuse(problem);
            return;
          }
          // the first state decides: a skeleton that does not fit the scene file leaves the page
          // the server's frames
          if (!scene_sent && !scene_dropped) {
            try {
              server.SetScene(SceneJson(*scene, s, width, height));
              scene_sent = true;
            } catch (const InputError& e) {
              server.DropScene();
              scene_dropped = true;
              std::fprintf(stderr, "viscera: the page shows server frames only: %s\n", e.what());
            }
          }
          if (!scene_sent) return;
          if (s.num_points != scene->initial_q.rows()) {
            refuse(
                Cat(s.num_points, " control points, the scene file has ", scene->initial_q.rows()));
            return;
          }
          ++skeletons;
          server.PostSkeleton(SkeletonJson(s, *scene, tools, camera));
        });
  }

  // the server draws frames only while someone watches them: renew its frame lease while a
  // page shows them (an MJPEG stream open, or /frame.jpg asked since the last renewal)
  SessionClient watcher(options.url, options.auth);
  auto next_watch = Clock::now();
  int64_t frame_requests = 0;
  const auto start = Clock::now();
  while (!signals.Received()) {
    bus.Pump(50);
    if (Clock::now() >= next_watch) {
      const MjpegServerStats now = server.stats();
      if (now.active_streams > 0 || now.frame_requests > frame_requests) {
        viscera_proto::session_request_t watch =
            MakeRequest(viscera_proto::session_request_t::kWatchFrames, options.session_id);
        watcher.Send(&watch);
      }
      frame_requests = now.frame_requests;
      next_watch = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                      std::chrono::duration<double>(kFrameWatchPeriodS));
    }
    if (options.count > 0 && frames.received() + skeletons >= options.count) break;
    if (options.seconds > 0 &&
        Clock::now() - start >= std::chrono::duration<double>(options.seconds))
      break;
  }
  if (refused > 0) {
    std::fprintf(stderr, "viscera: %lld skeleton state(s) refused: %s\n",
                 static_cast<long long>(refused), last_refusal.c_str());
  }
  const MjpegServerStats s = server.stats();
  std::fprintf(
      stderr,
      "viscera: served %lld frame parts to %lld stream(s), %lld skeleton messages to the pages\n",
      static_cast<long long>(s.parts_sent), static_cast<long long>(s.streams_opened),
      static_cast<long long>(s.messages_sent));
  return kFramesOk;
}

}  // namespace viscera::client
