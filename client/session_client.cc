#include "client/session_client.h"

#include <algorithm>
#include <chrono>

#include "bus/channels.h"
#include "bus/header.h"
#include "bus/message_auth.h"
#include "client/printable.h"

namespace viscera::client {
namespace {

using Clock = std::chrono::steady_clock;

Clock::time_point After(double seconds) {
  return Clock::now() +
         std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

int MillisLeft(Clock::time_point deadline) {
  const auto left =
      std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return static_cast<int>(std::clamp<int64_t>(left, 0, 100));
}

// Every string of a reply made printable: the CLI prints them, and whoever answers chooses them
// (a status carrying terminal escapes reached the user's terminal raw).
void MakePrintable(viscera_proto::session_reply_t* reply) {
  reply->message = Printable(reply->message);
  reply->server_id = Printable(reply->server_id);
  for (viscera_proto::session_status_t& s : reply->sessions) {
    for (std::string* text : {&s.server_id, &s.scene, &s.skin, &s.last_error})
      *text = Printable(*text);
    for (std::string& name : s.tool_names) name = Printable(name);
    for (std::string& name : s.target_names) name = Printable(name);
  }
}

}  // namespace

viscera_proto::session_request_t MakeRequest(int8_t command, int64_t session_id) {
  viscera_proto::session_request_t r{};
  r.header = bus::MakeHeader(session_id, 0);
  const std::vector<uint8_t> random = bus::RandomBytes(8);
  uint64_t id = 0;
  for (const uint8_t b : random) id = (id << 8) | b;
  r.request_id = static_cast<int64_t>(id >> 1) | 1;  // positive, never 0
  r.command = command;
  r.camera_up[2] = 1.0;
  r.camera_fov_deg = 60.0;
  return r;
}

SessionClient::SessionClient(const std::string& url, std::shared_ptr<const bus::MessageAuth> auth)
    : bus_(url), sender_(bus::NewSenderId()) {
  bus_.SetAuth(std::move(auth));
  // replies, statuses and heartbeats are small: a fake server's 33 MB list took 711 MB to decode
  bus_.SetMaxMessageSize(kMaxReplyBytes);
}

std::optional<viscera_proto::heartbeat_t> SessionClient::FindServer(const std::string& server_id,
                                                                    double timeout_s) {
  std::optional<viscera_proto::heartbeat_t> found;
  const bus::SubscriptionId sub = bus_.Subscribe<viscera_proto::heartbeat_t>(
      bus::kHeartbeatChannel, [&](const viscera_proto::heartbeat_t& hb, int64_t) {
        if (!bus::HeaderProblem(hb.header).empty()) return;
        if (!server_id.empty() && hb.server_id != server_id) return;
        if (!found) found = hb;
      });
  const auto deadline = After(timeout_s);
  while (!found && Clock::now() < deadline) bus_.Pump(MillisLeft(deadline));
  bus_.Unsubscribe(sub);
  return found;
}

bool SessionClient::Send(viscera_proto::session_request_t* request) {
  request->header.sender = sender_;
  request->header.seq = seq_++;
  request->header.utime = bus::WallMicros();
  return bus_.Publish(bus::kRequestChannel, *request);
}

std::vector<ServerInfo> SessionClient::HearServers(double listen_s, double timeout_s) {
  ServerDirectory directory;
  const bus::SubscriptionId sub = bus_.Subscribe<viscera_proto::heartbeat_t>(
      bus::kHeartbeatChannel,
      [&](const viscera_proto::heartbeat_t& hb, int64_t) { directory.Observe(hb); });
  const auto enough = After(std::min(listen_s, timeout_s));
  const auto deadline = After(timeout_s);
  while (Clock::now() < deadline && (Clock::now() < enough || directory.Servers().empty())) {
    bus_.Pump(MillisLeft(Clock::now() < enough ? enough : deadline));
  }
  bus_.Unsubscribe(sub);
  return directory.Servers();
}

std::vector<viscera_proto::session_reply_t> SessionClient::Request(
    viscera_proto::session_request_t request, double timeout_s, bool collect_all, double grace_s) {
  std::vector<viscera_proto::session_reply_t> replies;
  bool owner_answered = false;
  const bus::SubscriptionId sub = bus_.Subscribe<viscera_proto::session_reply_t>(
      bus::kReplyChannel, [&](const viscera_proto::session_reply_t& reply, int64_t) {
        if (reply.request_id != request.request_id || !bus::HeaderProblem(reply.header).empty()) {
          return;
        }
        replies.push_back(reply);
        MakePrintable(&replies.back());
        if (reply.result != viscera_proto::session_reply_t::kUnknownSession) owner_answered = true;
      });
  Send(&request);

  auto deadline = After(timeout_s);
  bool extended = false;
  while (Clock::now() < deadline) {
    bus_.Pump(MillisLeft(deadline));
    if (replies.empty()) continue;
    if (!collect_all && owner_answered) break;
    if (!extended) {
      // others may still answer: the owner of the session, or more servers for kList
      deadline = std::min(deadline, After(grace_s));
      extended = true;
    }
  }
  bus_.Unsubscribe(sub);
  // the owner's answer first
  std::stable_sort(replies.begin(), replies.end(), [](const auto& a, const auto& b) {
    return (a.result != viscera_proto::session_reply_t::kUnknownSession) >
           (b.result != viscera_proto::session_reply_t::kUnknownSession);
  });
  return replies;
}

}  // namespace viscera::client
