/// viscera: the thin command-line client of viscerad. Links the bus and the messages
/// only; every command is a few LCM messages and some printing.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <functional>
#include <iostream>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <viscera_proto/session_status_t.hpp>

#include "assessment/status_report.h"
#include "bus/channels.h"
#include "bus/header.h"
#include "bus/lcm_bus.h"
#include "bus/message_auth.h"
#include "client/driver.h"
#include "client/frame_commands.h"
#include "client/gesture.h"
#include "client/haptic_cli.h"
#include "client/haptic_command.h"
#include "client/keep_alive.h"
#include "client/server_directory.h"
#include "client/session_client.h"
#include "client/status_format.h"
#include "client/token_store.h"

namespace {

using viscera_proto::session_reply_t;
using viscera_proto::session_request_t;
using Json = nlohmann::ordered_json;

// Exit codes: 0 success, 1 local error (bad URL, no multicast route, bad file), 2 no
// server answered, 3 unknown session, 4 the server refused (or bad token, bad request);
// CLI11 reports bad flags with its own codes (100 and up).
constexpr int kLocalError = 1;
constexpr int kNoServer = 2;
constexpr int kUnknownSession = 3;
constexpr int kRefused = 4;

struct Common {
  std::string lcm_url;
  std::string key_file;
  std::string sessions_file;
  std::string token_hex;   ///< --token: refused (argv is readable by every local user)
  std::string token_file;  ///< --token-file: the session token (hex) in a file
  double timeout_s = 2.0;
  bool json = false;
};

struct ServersOptions {
  double timeout_s = 2.0;
};

std::shared_ptr<const viscera::bus::MessageAuth> LoadAuth(const Common& c) {
  if (c.key_file.empty()) return nullptr;
  return std::make_shared<viscera::bus::MessageAuth>(
      viscera::bus::MessageAuth::FromKeyFile(c.key_file));
}

int NoServer(const Common& c, const std::string& url, const char* what) {
  std::fprintf(stderr,
               "viscera: no server answered %s on %s within %g s (is viscerad running? for "
               "udpm://, does this network have a multicast route?%s)\n",
               what, url.c_str(), c.timeout_s,
               c.key_file.empty() ? "" : " does the server use the same --key-file?");
  return kNoServer;
}

// Exit code and message for a reply that is not kOk.
int ReplyError(const session_reply_t& reply, int64_t id) {
  switch (reply.result) {
    case session_reply_t::kOk: return 0;
    case session_reply_t::kUnknownSession:
      std::fprintf(stderr, "viscera: unknown session %lld\n", static_cast<long long>(id));
      return kUnknownSession;
    case session_reply_t::kBadToken:
      std::fprintf(
          stderr,
          "viscera: server %s refused: %s (this client has no valid token for session %lld)\n",
          reply.server_id.c_str(), reply.message.c_str(), static_cast<long long>(id));
      return kRefused;
    case session_reply_t::kReplayed:
      std::fprintf(stderr,
                   "viscera: server %s refused this command as replayed or stale: %s (nothing "
                   "changed; send it again)\n",
                   reply.server_id.c_str(), reply.message.c_str());
      return kRefused;
    default:
      std::fprintf(stderr, "viscera: server %s refused: %s\n", reply.server_id.c_str(),
                   reply.message.c_str());
      return kRefused;
  }
}

int RunServers(const std::string& url, const Common& c, const ServersOptions& options) {
  viscera::bus::LcmBus bus(url);
  bus.SetAuth(LoadAuth(c));
  viscera::client::ServerDirectory directory;
  bus.Subscribe<viscera_proto::heartbeat_t>(
      viscera::bus::kHeartbeatChannel,
      [&](const viscera_proto::heartbeat_t& msg, int64_t) { directory.Observe(msg); });

  // Listen for the whole timeout: every server beats once a second, so a timeout of
  // a little over a second hears each of them at least once.
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(options.timeout_s));
  for (auto now = Clock::now(); now < deadline; now = Clock::now()) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now);
    bus.Pump(static_cast<int>(std::max<int64_t>(left.count(), 1)));
  }

  if (directory.rejected() > 0) {
    std::fprintf(stderr, "viscera: ignored %lld heartbeat(s): %s\n",
                 static_cast<long long>(directory.rejected()), directory.last_rejection().c_str());
  }
  if (bus.stats().decode_failures > 0) {
    std::fprintf(stderr, "viscera: %lld malformed message(s) on %s\n",
                 static_cast<long long>(bus.stats().decode_failures),
                 viscera::bus::kHeartbeatChannel);
  }
  const auto servers = directory.Servers();
  if (servers.empty()) {
    std::fprintf(stderr,
                 "viscera: no server answered on %s within %g s (is viscerad running? "
                 "for udpm://, does this network have a multicast route?)\n",
                 url.c_str(), options.timeout_s);
    return kNoServer;
  }
  if (c.json) {
    std::cout << viscera::client::ServersToJson(servers).dump(2) << "\n";
  } else {
    std::cout << viscera::client::ServersToTable(servers);
  }
  return 0;
}

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

int RunCreate(const std::string& url, const Common& c, const CreateOptions& o) {
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
  viscera::client::SessionClient client(url, LoadAuth(c));
  std::string server_id = o.server;
  std::string placement;  // why this server, when the client chose it
  if (server_id.empty()) {
    // every server beats once a period: listen a little longer than one to hear them all
    const auto servers = client.HearServers(o.listen_s, c.timeout_s);
    if (servers.empty()) return NoServer(c, url, "(heartbeat)");
    const viscera::client::ServerInfo* best = viscera::client::PickServer(servers);
    if (best == nullptr) {
      std::fprintf(stderr, "viscera: every server is full (%s)\n",
                   viscera::client::ServersSummary(servers).c_str());
      return kRefused;
    }
    server_id = best->server_id;
    placement = "least loaded of " + viscera::client::ServersSummary(servers);
  } else if (!client.FindServer(server_id, c.timeout_s)) {
    return NoServer(c, url, server_id.c_str());
  }
  session_request_t request = viscera::client::MakeRequest(session_request_t::kCreate, 0);
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
  viscera::client::TokenStore store(c.sessions_file);
  store.Put(id, {reply.header.token, reply.server_id});
  if (!reply.message.empty())
    std::fprintf(stderr, "viscera: scene warnings: %s\n", reply.message.c_str());
  if (c.json) {
    Json j = {{"session", id},
              {"server_id", reply.server_id},
              {"placement", placement.empty() ? "--server" : placement},
              {"token", viscera::client::ToHex(reply.header.token)},
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

int RunList(const std::string& url, const Common& c) {
  viscera::client::SessionClient client(url, LoadAuth(c));
  const auto replies =
      client.Request(viscera::client::MakeRequest(session_request_t::kList, 0), c.timeout_s,
                     /*collect_all=*/true, /*grace_s=*/0.5);
  if (replies.empty()) return NoServer(c, url, "the list request");
  std::vector<viscera_proto::session_status_t> all;
  for (const auto& r : replies) all.insert(all.end(), r.sessions.begin(), r.sessions.end());
  std::sort(all.begin(), all.end(),
            [](const auto& a, const auto& b) { return a.header.session_id < b.header.session_id; });
  if (c.json) {
    Json array = Json::array();
    for (const auto& s : all) array.push_back(viscera::client::StatusToJson(s));
    std::cout << array.dump(2) << "\n";
  } else {
    std::cout << viscera::client::StatusTable(all);
  }
  return 0;
}

std::vector<uint8_t> TokenFor(const Common& c, int64_t id, std::string* server_id) {
  // a token from a file or the environment, never from argv (/proc/PID/cmdline)
  if (!c.token_file.empty()) {
    std::ifstream in(c.token_file);
    std::string hex;
    viscera::ThrowUnless(static_cast<bool>(in >> hex), "cannot read a token from '", c.token_file,
                         "'");
    return viscera::client::FromHex(hex);
  }
  if (const char* env = std::getenv("VISCERA_TOKEN"); env != nullptr && env[0] != '\0') {
    return viscera::client::FromHex(env);
  }
  viscera::client::TokenStore store(c.sessions_file);
  const viscera::client::StoredSession* s = store.Find(id);
  if (s == nullptr) return {};
  if (server_id != nullptr) *server_id = s->server_id;
  return s->token;
}

void PrintStatus(const Common& c, const viscera_proto::session_status_t& s) {
  if (c.json) {
    std::cout << viscera::client::StatusToJson(s).dump(c.json ? -1 : 2) << std::endl;
  } else {
    std::cout << viscera::client::StatusTable({s}) << std::flush;
  }
}

struct StatusOptions {
  int64_t id = 0;
  bool watch = false;
  int count = 0;
};

// Asks for one session's status: 0 with the status in *out, or the exit code to return.
int FetchStatus(viscera::client::SessionClient& client, const std::string& url, const Common& c,
                int64_t id, viscera_proto::session_status_t* out) {
  const auto replies =
      client.Request(viscera::client::MakeRequest(session_request_t::kStatus, id), c.timeout_s);
  if (replies.empty()) return NoServer(c, url, "the status request");
  if (const int rc = ReplyError(replies.front(), id); rc != 0) return rc;
  if (replies.front().num_sessions < 1) return kRefused;
  *out = replies.front().sessions[0];
  return 0;
}

int RunStatus(const std::string& url, const Common& c, const StatusOptions& o) {
  viscera::client::SessionClient client(url, LoadAuth(c));
  viscera_proto::session_status_t status;
  if (const int rc = FetchStatus(client, url, c, o.id, &status); rc != 0) return rc;
  if (!o.watch) {
    const Json j = viscera::client::StatusToJson(status);
    if (c.json) {
      std::cout << j.dump(2) << "\n";
    } else {
      std::cout << viscera::client::StatusTable({status});
    }
    return 0;
  }
  // --watch: every status the session publishes, one line (or JSON object) each
  PrintStatus(c, status);
  int printed = 1;
  bool stopped = false;
  client.bus().Subscribe<viscera_proto::session_status_t>(
      viscera::bus::SessionChannel(viscera::bus::kStatusPrefix, o.id),
      [&](const viscera_proto::session_status_t& s, int64_t) {
        PrintStatus(c, s);
        ++printed;
        if (s.state == viscera_proto::session_status_t::kStopped) stopped = true;
      });
  auto last = std::chrono::steady_clock::now();
  int last_printed = printed;
  while (!stopped && (o.count <= 0 || printed < o.count)) {
    client.bus().Pump(100);
    const auto now = std::chrono::steady_clock::now();
    if (printed != last_printed) {
      last = now;
      last_printed = printed;
    } else if (now - last > std::chrono::duration<double>(std::max(c.timeout_s, 2.0))) {
      std::fprintf(stderr, "viscera: session %lld went silent\n", static_cast<long long>(o.id));
      return kNoServer;
    }
  }
  return 0;
}

// The session's assessment (docs/assessment.md) from its status: now, or with --final the one
// its last status carries when it ends (the same as the JSON the server writes by its record).
int RunReport(const std::string& url, const Common& c, int64_t id, bool final_only) {
  viscera::client::SessionClient client(url, LoadAuth(c));
  viscera_proto::session_status_t status;
  if (const int rc = FetchStatus(client, url, c, id, &status); rc != 0) return rc;
  if (final_only) {
    bool ended = false;
    auto last = std::chrono::steady_clock::now();
    client.bus().Subscribe<viscera_proto::session_status_t>(
        viscera::bus::SessionChannel(viscera::bus::kStatusPrefix, id),
        [&](const viscera_proto::session_status_t& s, int64_t) {
          last = std::chrono::steady_clock::now();
          if (ended) return;
          status = s;
          ended = s.state == viscera_proto::session_status_t::kStopped ||
                  s.state == viscera_proto::session_status_t::kFaulted;
        });
    while (!ended) {
      client.bus().Pump(100);
      if (std::chrono::steady_clock::now() - last >
          std::chrono::duration<double>(std::max(c.timeout_s, 2.0))) {
        std::fprintf(stderr, "viscera: session %lld went silent before it ended\n",
                     static_cast<long long>(id));
        return kNoServer;
      }
    }
  }
  const viscera::assessment::Report report = viscera::assessment::ReportFromStatus(status);
  if (c.json) {
    std::cout << viscera::assessment::ToJson(report).dump(2) << "\n";
  } else {
    std::cout << viscera::assessment::FormatReport(report);
  }
  return 0;
}

// destroy, reset, pause, resume, camera: one request with the session's token
int RunCommand(const std::string& url, const Common& c, int8_t command, int64_t id,
               const std::function<void(session_request_t*)>& fill = nullptr) {
  std::string server_id;
  const std::vector<uint8_t> token = TokenFor(c, id, &server_id);
  viscera::client::SessionClient client(url, LoadAuth(c));
  session_request_t request = viscera::client::MakeRequest(command, id);
  request.header.token = token;
  request.header.token_len = static_cast<int32_t>(token.size());
  if (fill) fill(&request);
  const auto replies = client.Request(request, c.timeout_s);
  if (replies.empty()) return NoServer(c, url, "the request");
  const session_reply_t& reply = replies.front();
  if (const int rc = ReplyError(reply, id); rc != 0) return rc;
  if (command == session_request_t::kDestroy) {
    viscera::client::TokenStore store(c.sessions_file);
    store.Erase(id);
  }
  if (c.json) {
    Json j = {{"session", id}, {"server_id", reply.server_id}, {"ok", true}};
    if (reply.num_sessions > 0) j["status"] = viscera::client::StatusToJson(reply.sessions[0]);
    std::cout << j.dump(2) << "\n";
  } else if (reply.num_sessions > 0) {
    std::cout << viscera::client::StatusTable({reply.sessions[0]});
  } else {
    std::printf("ok\n");
  }
  return 0;
}

struct DriveCli {
  int64_t id = 0;
  std::string script;
  std::string gesture;
  double pose_rate_hz = 100.0;
};

int RunDrive(const std::string& url, const Common& c, const DriveCli& o) {
  if (o.script.empty() == o.gesture.empty()) {
    std::fprintf(stderr, "viscera: drive needs --script FILE or --gesture clearing\n");
    return kLocalError;
  }
  if (!o.gesture.empty() && o.gesture != "clearing") {
    std::fprintf(stderr, "viscera: unknown gesture '%s' (known: clearing)\n", o.gesture.c_str());
    return kLocalError;
  }
  const viscera::script::ToolScript script =
      o.script.empty() ? viscera::client::ClearingGesture() : viscera::client::LoadScript(o.script);
  viscera::client::SessionClient client(url, LoadAuth(c));
  // the session must exist and have the tool
  viscera_proto::session_status_t status;
  if (const int rc = FetchStatus(client, url, c, o.id, &status); rc != 0) return rc;
  viscera::client::DriveOptions options;
  options.session_id = o.id;
  options.token = TokenFor(c, o.id, nullptr);
  options.tool_names = status.tool_names;
  options.pose_rate_hz = o.pose_rate_hz;
  for (const std::string& name : script.tools()) {
    if (std::find(options.tool_names.begin(), options.tool_names.end(), name) ==
        options.tool_names.end()) {
      std::fprintf(
          stderr, "viscera: the script drives tool \"%s\" but session %lld has %s\n", name.c_str(),
          static_cast<long long>(o.id),
          options.tool_names.empty() ? "no tools (its scene has no [[tool]])" : "other tools");
      return kRefused;
    }
  }
  // poses renew the lease too; the keep-alive covers pauses in a script
  std::optional<viscera::client::KeepAlive> keep_alive;
  keep_alive.emplace(&client, o.id, options.token,
                     viscera::client::KeepAlivePeriod(status.lease_s));
  const viscera::client::DriveResult r = viscera::client::Drive(client, script, options);
  keep_alive.reset();
  const auto after =
      client.Request(viscera::client::MakeRequest(session_request_t::kStatus, o.id), c.timeout_s);
  if (after.empty() || after.front().num_sessions < 1)
    return NoServer(c, url, "the status request");
  const auto& s = after.front().sessions[0];
  if (s.replayed > status.replayed) {
    std::fprintf(stderr,
                 "viscera: session %lld refused %lld messages as replayed or stale while driving "
                 "(last: %s)\n",
                 static_cast<long long>(o.id), static_cast<long long>(s.replayed - status.replayed),
                 s.last_error.c_str());
  }
  if (c.json) {
    std::cout << Json{{"session", o.id},
                      {"drive", viscera::client::DriveToJson(r)},
                      {"status", viscera::client::StatusToJson(s)}}
                     .dump(2)
              << "\n";
  } else {
    std::printf("drove session %lld for %.2f s: %lld poses sent at %g Hz, %lld forces received\n",
                static_cast<long long>(o.id), r.duration_s, static_cast<long long>(r.poses_sent),
                o.pose_rate_hz, static_cast<long long>(r.forces_received));
    std::printf(
        "force      max |F| %.3f N on %s (%.3f, %.3f, %.3f), mean |F| %.3f N, clamped %lld\n",
        r.max_force_n, r.tool_at_max.c_str(), r.force_at_max.x(), r.force_at_max.y(),
        r.force_at_max.z(), r.mean_force_n, static_cast<long long>(r.clamped));
    std::printf(
        "round trip pose -> force p50 %.0f us, p99 %.0f us, max %.0f us (%lld poses answered)\n",
        r.round_trip_p50_us, r.round_trip_p99_us, r.round_trip_max_us,
        static_cast<long long>(r.poses_answered));
    std::printf(
        "mechanics  %.0f of %.0f Hz, %lld deadline %s, step p50 %.0f us p99 %.0f us, "
        "jitter p99 %.0f us, %lld rejected\n",
        s.achieved_rate_hz, s.rate_hz, static_cast<long long>(s.deadline_misses),
        s.deadline_misses == 1 ? "miss" : "misses", s.step_cost_p50_us, s.step_cost_p99_us,
        s.jitter_p99_us, static_cast<long long>(s.rejected));
  }
  if (r.forces_received == 0) {
    std::fprintf(stderr, "viscera: no force feedback received\n");
    return kNoServer;
  }
  return 0;
}

int RunHapticCli(const std::string& url, const Common& c, viscera::client::HapticCli o) {
  viscera::client::HapticCommand& h = o.command;
  viscera::client::SessionClient client(url, LoadAuth(c));
  // the session must exist and have the tool
  viscera_proto::session_status_t status;
  if (const int rc = FetchStatus(client, url, c, h.session_id, &status); rc != 0) return rc;
  const auto it = std::find(status.tool_names.begin(), status.tool_names.end(), h.tool_name);
  if (it == status.tool_names.end()) {
    std::fprintf(stderr, "viscera: session %lld has no tool \"%s\"\n",
                 static_cast<long long>(h.session_id), h.tool_name.c_str());
    return kRefused;
  }
  h.tool = static_cast<int>(it - status.tool_names.begin());
  h.token = TokenFor(c, h.session_id, nullptr);
  h.json = c.json;
  h.live = !c.json && !o.quiet && isatty(STDERR_FILENO) == 1;
  h.loop.impairment.delay_s = o.delay_ms * 1e-3;
  h.loop.impairment.jitter_s = o.jitter_ms * 1e-3;
  h.loop.model.stale_after_s = o.stale_ms * 1e-3;
  h.loop.model.fade_s = o.fade_ms * 1e-3;
  h.loop.spin_ns = o.spin_us < 0.0 ? -1 : static_cast<int64_t>(o.spin_us * 1e3);
  h.loop.deadband_m = o.deadband_mm * 1e-3;
  h.loop.passivity = !o.no_passivity;
  return viscera::client::RunHaptic(client, h);
}

// A few lines of examples for a command's --help.
std::string ExamplesFor(const std::string& command) {
  static const std::map<std::string, std::string> examples = {
      {"servers",
       "  viscera servers              # who is there, what each holds and why\n"
       "  viscera servers --json\n"},
      {"create",
       "  viscera create cavity --json                 # the least loaded server with room\n"
       "  viscera create cavity --frame-rate -1        # no frames: costs a step only\n"
       "  viscera create --scene-file my_scene.toml --rate 500\n"},
      {"list", "  viscera list\n"},
      {"status", "  viscera status ID\n  viscera status ID --watch --count 8\n"},
      {"report", "  viscera report ID\n  viscera report ID --final --json\n"},
      {"drive",
       "  viscera drive ID --gesture clearing\n  viscera drive ID --script scenes/clearing.csv "
       "--pose-rate 500\n"},
      {"haptic",
       "  viscera haptic ID --tool right --device sim --script scenes/clearing.csv\n"
       "  viscera haptic ID --tool right --device sim --script scenes/clearing.csv --realtime "
       "80\n"},
      {"camera", "  viscera camera ID --eye -0.02 -0.14 0.20 --target -0.01 0.01 0.05\n"},
      {"destroy", "  viscera destroy ID\n"},
      {"pause", "  viscera pause ID\n"},
      {"resume", "  viscera resume ID\n"},
      {"reset", "  viscera reset ID\n"},
      {"frames", "  viscera frames ID --out out/frames --count 5\n"},
      {"record", "  viscera record ID --out out/clip.mp4 --seconds 10\n"},
      {"view", "  viscera view ID --http 127.0.0.1:8080\n"},
      {"keygen",
       "  viscera keygen psk    # then viscerad --key-file psk, viscera --key-file psk ...\n"},
  };
  const auto it = examples.find(command);
  return it == examples.end() ? std::string() : "\nExamples:\n" + it->second;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"viscera: client of the viscera haptic server"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("viscera ") + VISCERA_VERSION);
  // the common options belong to `viscera` and are matched there from any command (listed
  // once, by viscera --help, rather than in every command's help)
  app.fallthrough();
  Common common;
  common.sessions_file = viscera::client::DefaultTokenStorePath();
  auto add_common = [&](CLI::App* cmd) {
    if (cmd != &app) {
      cmd->footer(ExamplesFor(cmd->get_name()) +
                  "\nCommon options (--lcm-url, --key-file, --sessions, --timeout, --json): "
                  "viscera --help");
      return;
    }
    cmd->add_option(
        "--lcm-url", common.lcm_url,
        "LCM URL (default: $LCM_DEFAULT_URL, else " + std::string(viscera::bus::kDefaultUrl) + ")");
    cmd->add_option("--key-file", common.key_file, "Pre-shared key file (sign and check MACs)");
    cmd->add_option("--sessions", common.sessions_file, "Where session tokens are kept")
        ->capture_default_str();
    cmd->add_option("--timeout", common.timeout_s, "Seconds to wait for a server")
        ->check(CLI::Range(0.01, 3600.0))
        ->capture_default_str();
    cmd->add_flag("--json", common.json, "Print JSON");
  };
  add_common(&app);
  // a session token: --token-file or $VISCERA_TOKEN (default: from --sessions); --token is
  // kept only to say why it is refused
  auto add_token = [&](CLI::App* cmd) {
    cmd->add_option(
        "--token-file", common.token_file,
        "File holding the session token (hex; or $VISCERA_TOKEN; default: from --sessions)");
    cmd->add_option("--token", common.token_hex, "Refused: use --token-file or $VISCERA_TOKEN")
        ->group("");
  };

  ServersOptions servers_options;
  CLI::App* servers =
      app.add_subcommand("servers", "List the servers heard on the heartbeat channel");
  add_common(servers);

  CreateOptions create_options;
  CLI::App* create = app.add_subcommand("create", "Start a session");
  add_common(create);
  create->add_option("scene", create_options.scene, "Scene name in the server's scene directory");
  create->add_option("--scene-file", create_options.scene_file, "Send this scene file inline");
  create->add_option("--server", create_options.server,
                     "Server id (default: the least loaded server with room)");
  create
      ->add_option("--listen", create_options.listen_s,
                   "Seconds to hear heartbeats before choosing a server")
      ->check(CLI::Range(0.05, 60.0))
      ->capture_default_str();
  create
      ->add_option("--build-timeout", create_options.build_timeout_s,
                   "Seconds to wait for the heard server to build the scene and answer")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str();
  create
      ->add_option("--rate", create_options.rate_hz,
                   "Mechanics rate (Hz; default: the scene's; servers cap it at their --max-rate, "
                   "1000 by default)")
      ->check(CLI::Range(1.0, 1000.0));
  create->add_option("--skeleton-rate", create_options.skeleton_rate_hz,
                     "Skeleton state rate (Hz)");
  create->add_option("--skin", create_options.skin,
                     "Skin of the frames: parametric, implicit, convolution or hybrid");
  create->add_option("--width", create_options.width, "Frame width (pixels)");
  create->add_option("--height", create_options.height, "Frame height (pixels)");
  create->add_option("--frame-rate", create_options.frame_rate_hz,
                     "Frames per second (Hz; default: the server's, 25; < 0: no frames)");
  create->add_option("--jpeg-quality", create_options.jpeg_quality, "JPEG quality (1..100)")
      ->check(CLI::Range(1, 100));

  CLI::App* list = app.add_subcommand("list", "Status of every session of every server");
  add_common(list);

  StatusOptions status_options;
  CLI::App* status = app.add_subcommand("status", "Status of a session");
  add_common(status);
  status->add_option("id", status_options.id, "Session id")->required();
  status->add_flag("--watch", status_options.watch, "Print every status until the session stops");
  status->add_option("--count", status_options.count, "With --watch: stop after N statuses");

  int64_t report_id = 0;
  bool report_final = false;
  CLI::App* report =
      app.add_subcommand("report", "Assessment of a session: handling metrics and target exposure");
  add_common(report);
  report->add_option("id", report_id, "Session id")->required();
  report->add_flag("--final", report_final,
                   "Wait for the session to end and print its final assessment");

  DriveCli drive_options;
  CLI::App* drive = app.add_subcommand("drive", "Drive a session's tool along a path");
  add_common(drive);
  drive->add_option("id", drive_options.id, "Session id")->required();
  drive->add_option("--script", drive_options.script,
                    "Tool script (CSV t,tool,x,y,z,qw,qx,qy,qz,jaw; scenes/clearing.csv)");
  drive->add_option("--gesture", drive_options.gesture, "Built-in gesture: clearing");
  drive->add_option("--pose-rate", drive_options.pose_rate_hz, "Poses per second")
      ->check(CLI::Range(1.0, 10000.0))
      ->capture_default_str();
  add_token(drive);

  viscera::client::HapticCli haptic_options;
  CLI::App* haptic = app.add_subcommand(
      "haptic", "Run a haptic device loop on a session's tool (docs/haptics.md)");
  add_common(haptic);
  viscera::client::AddHapticOptions(haptic, &haptic_options);
  add_token(haptic);

  int64_t camera_id = 0;
  std::vector<double> eye{0.0, -0.3, 0.3}, target{0.0, 0.0, 0.0}, up{0.0, 0.0, 1.0};
  double fov = 60.0;
  CLI::App* camera = app.add_subcommand("camera", "Set a session's laparoscope camera");
  add_common(camera);
  camera->add_option("id", camera_id, "Session id")->required();
  camera->add_option("--eye", eye, "Eye x y z (m)")->expected(3)->required();
  camera->add_option("--target", target, "Look-at point x y z (m)")->expected(3)->required();
  camera->add_option("--up", up, "Up vector")->expected(3);
  camera->add_option("--fov", fov, "Vertical field of view (degrees)");
  add_token(camera);

  struct Simple {
    const char* name;
    const char* help;
    int8_t command;
    int64_t id = 0;
    CLI::App* app = nullptr;
  };
  std::vector<Simple> simple = {
      {"destroy", "Stop a session and close its record", session_request_t::kDestroy},
      {"pause", "Stop stepping a session", session_request_t::kPause},
      {"resume", "Step a paused session again", session_request_t::kResume},
      {"reset", "Put a session back to its scene's start", session_request_t::kReset},
  };
  for (Simple& s : simple) {
    s.app = app.add_subcommand(s.name, s.help);
    add_common(s.app);
    s.app->add_option("id", s.id, "Session id")->required();
    add_token(s.app);
  }

  // frames, record, view: listen to one session's frame stream
  viscera::client::FrameListenOptions listen;
  std::string frames_dir, record_file, view_address = "127.0.0.1:8080", view_scene,
                                       view_scene_dir = "scenes";
  double record_fps = 0.0;
  auto add_listen = [&](CLI::App* cmd) {
    add_common(cmd);
    cmd->add_option("id", listen.session_id, "Session id")->required();
    cmd->add_option("--count", listen.count, "Stop after N frames")->check(CLI::NonNegativeNumber);
    cmd->add_option("--seconds", listen.seconds, "Stop after S seconds")
        ->check(CLI::NonNegativeNumber);
  };
  CLI::App* frames = app.add_subcommand("frames", "Save a session's frames as JPEG files");
  add_listen(frames);
  frames->add_option("--out", frames_dir, "Directory for frame_000000.jpg, ...")->required();
  CLI::App* record = app.add_subcommand("record", "Record a session's frames into a video");
  add_listen(record);
  record->add_option("--out", record_file, "Video file (.mp4: MPEG-4 part 2, .avi: MJPEG)")
      ->required();
  record
      ->add_option("--fps", record_fps,
                   "Frames per second of the video (default: the session's frame rate)")
      ->check(CLI::Range(1.0, 240.0));
  CLI::App* view = app.add_subcommand("view",
                                      "Show a session in a browser: drawn by the page from its "
                                      "skeleton (WebGL), or the server's frames");
  add_listen(view);
  view->add_option("--http", view_address, "Address to serve on, HOST:PORT (keep it on loopback)")
      ->capture_default_str();
  view->add_option(
      "--scene", view_scene,
      "The session's scene file, for the page to draw from (default: SCENE-DIR/<its scene>.toml)");
  view->add_option("--scene-dir", view_scene_dir, "Where the session's named scene is looked for")
      ->capture_default_str();

  std::string keygen_path;
  CLI::App* keygen = app.add_subcommand("keygen", "Write a new pre-shared key file (mode 0600)");
  add_common(keygen);
  keygen->add_option("file", keygen_path, "Key file to write")->required();

  CLI11_PARSE(app, argc, argv);
  if (!common.token_hex.empty()) {
    std::fprintf(stderr,
                 "viscera: --token is refused: a command line is readable by every local user "
                 "(/proc/PID/cmdline); put the token in a file (--token-file FILE, mode 0600) or "
                 "in $VISCERA_TOKEN\n");
    return kLocalError;
  }
  try {
    const std::string url = viscera::bus::ResolveUrl(common.lcm_url);
    if (servers->parsed()) {
      servers_options.timeout_s = common.timeout_s;
      return RunServers(url, common, servers_options);
    }
    if (create->parsed()) return RunCreate(url, common, create_options);
    if (list->parsed()) return RunList(url, common);
    if (status->parsed()) return RunStatus(url, common, status_options);
    if (report->parsed()) return RunReport(url, common, report_id, report_final);
    if (drive->parsed()) return RunDrive(url, common, drive_options);
    if (haptic->parsed()) return RunHapticCli(url, common, haptic_options);
    if (camera->parsed()) {
      return RunCommand(url, common, session_request_t::kCamera, camera_id,
                        [&](session_request_t* r) {
                          for (int a = 0; a < 3; ++a) {
                            r->camera_eye[a] = eye[static_cast<size_t>(a)];
                            r->camera_target[a] = target[static_cast<size_t>(a)];
                            r->camera_up[a] = up[static_cast<size_t>(a)];
                          }
                          r->camera_fov_deg = fov;
                        });
    }
    for (const Simple& s : simple) {
      if (s.app->parsed()) return RunCommand(url, common, s.command, s.id);
    }
    if (frames->parsed() || record->parsed() || view->parsed()) {
      listen.url = url;
      listen.auth = LoadAuth(common);
      listen.timeout_s = std::max(common.timeout_s, 5.0);  // the first frame may need a scene built
      listen.json = common.json;
      // a viewer with the session's token keeps the session alive while it watches
      viscera::client::SessionClient keeper(url, listen.auth);
      const std::vector<uint8_t> token = TokenFor(common, listen.session_id, nullptr);
      if (token.empty()) {
        std::fprintf(
            stderr,
            "viscera: no token for session %lld here: watching without renewing its lease\n",
            static_cast<long long>(listen.session_id));
      }
      double lease_s = 0.0;
      if (!token.empty()) {
        const auto replies = keeper.Request(
            viscera::client::MakeRequest(session_request_t::kStatus, listen.session_id),
            common.timeout_s);
        if (!replies.empty() && replies.front().num_sessions > 0)
          lease_s = replies.front().sessions[0].lease_s;
      }
      viscera::client::KeepAlive keep_alive(&keeper, listen.session_id, token,
                                            viscera::client::KeepAlivePeriod(lease_s));
      // frames and record take every frame: they renew the frame lease (view does while its page
      // shows server frames)
      std::optional<viscera::client::KeepAlive> watch;
      if (!view->parsed()) {
        watch.emplace(&keeper, listen.session_id, token, viscera::client::kFrameWatchPeriodS,
                      session_request_t::kWatchFrames);
      }
      if (frames->parsed()) return viscera::client::SaveFrames(listen, frames_dir);
      if (record->parsed()) return viscera::client::RecordVideo(listen, record_file, record_fps);
      return viscera::client::ViewOverHttp(listen, view_address, view_scene, view_scene_dir);
    }
    if (keygen->parsed()) {
      viscera::bus::MessageAuth::WriteKeyFile(keygen_path);
      std::printf("wrote a new key to %s\n", keygen_path.c_str());
      return 0;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "viscera: %s\n", e.what());
    return kLocalError;
  }
  return kLocalError;
}
