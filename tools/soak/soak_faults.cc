#include "tools/soak/soak_faults.h"

#include <fcntl.h>
#include <spawn.h>
#include <unistd.h>

#include <fstream>
#include <random>

#include <viscera_proto/heartbeat_t.hpp>
#include <viscera_proto/tool_pose_t.hpp>

#include "bus/channels.h"
#include "bus/header.h"
#include "client/token_store.h"

extern char** environ;

namespace viscera::soak {
namespace {

using viscera_proto::session_reply_t;
using viscera_proto::session_request_t;

constexpr double kReplyTimeout = 5.0;  // s: a create may wait for a scene to be built

session_reply_t Ask(client::SessionClient& client, session_request_t request) {
  const auto replies = client.Request(std::move(request), kReplyTimeout);
  if (replies.empty()) {
    session_reply_t none{};
    none.result = session_reply_t::kRefused;
    none.message = "no reply";
    return none;
  }
  return replies.front();
}

}  // namespace

Created CreateSession(client::SessionClient& client, const std::string& server_id,
                      const std::string& scene_name, const std::string& scene_toml,
                      double frame_rate_hz) {
  session_request_t r = client::MakeRequest(session_request_t::kCreate, 0);
  r.server_id = server_id;
  r.scene_name = scene_name;
  r.scene_toml = scene_toml;
  r.frame_rate_hz = frame_rate_hz;
  r.frame_width = frame_rate_hz > 0 ? 160 : 0;
  r.frame_height = frame_rate_hz > 0 ? 120 : 0;
  const session_reply_t reply = Ask(client, r);
  Created c;
  if (reply.result != session_reply_t::kOk) {
    c.refusal = reply.message.empty() ? "refused" : reply.message;
    return c;
  }
  c.id = reply.header.session_id;
  c.token = reply.header.token;
  return c;
}

bool DestroySession(client::SessionClient& client, const Created& session) {
  session_request_t r = client::MakeRequest(session_request_t::kDestroy, session.id);
  r.header.token = session.token;
  r.header.token_len = static_cast<int32_t>(session.token.size());
  return Ask(client, r).result == session_reply_t::kOk;
}

void FloodPoses(bus::LcmBus& bus, const Created& session, int count) {
  const std::string channel = bus::SessionChannel(bus::kPosePrefix, session.id);
  viscera_proto::tool_pose_t pose{};
  const int64_t sender = bus::NewSenderId();
  for (int k = 0; k < count; ++k) {
    pose.header = bus::MakeHeader(session.id, k);
    pose.header.sender = sender;
    pose.header.token = session.token;
    pose.header.token_len = static_cast<int32_t>(session.token.size());
    pose.tool = 0;
    pose.position[2] = 0.2;
    pose.orientation[0] = 1.0;
    pose.jaw = 1.0;
    bus.Publish(channel, pose);
  }
}

int SendMalformed(bus::LcmBus& bus, int64_t session_id, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> garbage(200);
  for (uint8_t& g : garbage) g = static_cast<uint8_t>(rng());
  const std::string pose_channel = bus::SessionChannel(bus::kPosePrefix, session_id);
  int sent = 0;
  for (const std::string& channel : {std::string(bus::kRequestChannel), pose_channel}) {
    bus.PublishRaw(channel, garbage.data(), static_cast<int>(garbage.size()));
    bus.PublishRaw(channel, garbage.data(), 5);  // truncated
    viscera_proto::heartbeat_t wrong_type{};
    wrong_type.header = bus::MakeHeader(session_id, 0);
    bus.Publish(channel, wrong_type);
    // a valid request with one byte flipped in its body: decodes wrongly or not at all
    session_request_t r = client::MakeRequest(session_request_t::kPause, session_id);
    std::vector<uint8_t> bytes(static_cast<size_t>(r.getEncodedSize()));
    r.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    bytes[bytes.size() / 2] ^= 0x5a;
    bus.PublishRaw(channel, bytes.data(), static_cast<int>(bytes.size()));
    sent += 4;
  }
  return sent;
}

std::string SendOversize(client::SessionClient& client, const std::string& server_id,
                         int max_bytes) {
  session_request_t r = client::MakeRequest(session_request_t::kCreate, 0);
  r.server_id = server_id;
  r.scene_toml = std::string(static_cast<size_t>(max_bytes) + 1000, '#');
  const session_reply_t reply = Ask(client, r);
  return reply.message == "no reply" ? "" : reply.message;
}

int SendMalformedScenes(client::SessionClient& client, const std::string& server_id) {
  const std::string tube =
      "[intestine]\nlength = 0.4\nradius = 0.0125\nmass = 0.1\ncontrol_points = "
      "21\n[intestine.shape]\nkind = \"straight\"\n";
  const std::vector<std::string> scenes = {
      "[intestine\nlength = ",                                                // not TOML
      "[intestine]\nlength = -1\n",                                           // bad value
      tube + "[[obstacle]]\nkind = \"mesh\"\nfile = \"/dev/zero\"\n",         // a device
      tube + "[[obstacle]]\nkind = \"mesh\"\nfile = \"../../etc/passwd\"\n",  // out of the dir
      std::string(tube).replace(tube.find("= 21"), 4, "= 100000000"),         // over budget
      tube + "[simulation]\nsettle = 1e9\n",                                  // endless settle
  };
  int refused = 0;
  for (const std::string& scene : scenes) {
    if (!CreateSession(client, server_id, "", scene, -1.0).refusal.empty()) ++refused;
  }
  return refused;
}

std::string UnstableScene() {
  return "[simulation]\nrate_hz = 100\nsubsteps = 1\nintegrator = \"rk4\"\n"
         "[intestine]\nlength = 0.5\nradius = 0.0125\nmass = 0.12\n"
         "control_points = 41\nstretch_stiffness = 1.0e4\nbend_stiffness = 1.0e-4\n"
         "[intestine.shape]\nkind = \"serpentine\"\nstart = [0.0, 0.0, 0.1]\n"
         "amplitude = 0.05\nwavelength = 0.2\n";
}

pid_t StartDriver(const std::string& viscera, const std::string& url, int64_t id,
                  const std::vector<uint8_t>& token, const std::string& script) {
  std::vector<std::string> args = {viscera,     "drive", std::to_string(id), "--script", script,
                                   "--lcm-url", url,     "--pose-rate",      "500"};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  // the token in the environment, never on the command line (/proc/PID/cmdline)
  std::string token_env = "VISCERA_TOKEN=" + client::ToHex(token);
  std::vector<char*> env;
  for (char** e = environ; *e != nullptr; ++e) {
    if (std::string(*e).rfind("VISCERA_TOKEN=", 0) != 0) env.push_back(*e);
  }
  env.push_back(token_env.data());
  env.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  if (posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), env.data()) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&actions);
  return pid;
}

ProcessFigures Figures(pid_t pid) {
  ProcessFigures f;
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("VmRSS:", 0) == 0) f.rss_kb = std::stoll(line.substr(6));
    if (line.rfind("Threads:", 0) == 0) f.threads = std::stoi(line.substr(8));
  }
  return f;
}

}  // namespace viscera::soak
