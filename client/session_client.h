#pragma once
/// SessionClient: the request/reply side of the protocol for the thin client (and for
/// tests and tools): find a server, send a session_request_t, wait for its reply.
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <viscera_proto/heartbeat_t.hpp>
#include <viscera_proto/session_reply_t.hpp>
#include <viscera_proto/session_request_t.hpp>

#include "bus/lcm_bus.h"
#include "client/server_directory.h"

namespace viscera::client {

/// A request with a fresh random request_id and a header for `session_id`; every other
/// field zero or empty.
viscera_proto::session_request_t MakeRequest(int8_t command, int64_t session_id);

class SessionClient {
 public:
  /// Messages larger than this are dropped before decoding (replies, statuses, heartbeats).
  static constexpr int kMaxReplyBytes = 1 << 20;

  /// @throws InputError when LCM cannot open `url`.
  SessionClient(const std::string& url, std::shared_ptr<const bus::MessageAuth> auth);

  /// The first server heard on the heartbeat channel within `timeout_s` (its latest
  /// heartbeat), preferring `server_id` when not empty (then only that one counts).
  std::optional<viscera_proto::heartbeat_t> FindServer(const std::string& server_id,
                                                       double timeout_s);

  /// Publishes `request` (its sender, seq and utime are set here) without waiting for a reply.
  /// Thread-safe (a keep-alive thread and the owner may both send).
  bool Send(viscera_proto::session_request_t* request);

  /// Every server heard on the heartbeat channel, sorted by id: listens `listen_s` (a little
  /// over one heartbeat period hears each running server once), and longer, up to
  /// `timeout_s`, while none has been heard yet (one that is starting).
  std::vector<ServerInfo> HearServers(double listen_s, double timeout_s);

  /// Publishes `request` (its sender, seq and utime are set here) and waits up to `timeout_s` for
  /// replies with its request_id. Returns at the first kOk reply; other replies (kUnknownSession
  /// from servers that do not hold the session) keep it waiting `grace_s` more for an owner. With
  /// `collect_all`, waits the whole `grace_s` after the first reply and returns all (for kList).
  /// Empty when no server answered.
  std::vector<viscera_proto::session_reply_t> Request(viscera_proto::session_request_t request,
                                                      double timeout_s, bool collect_all = false,
                                                      double grace_s = 0.3);

  bus::LcmBus& bus() { return bus_; }
  /// The sender id of this client's requests (header.sender): one per sequence counter.
  int64_t sender() const { return sender_; }

 private:
  bus::LcmBus bus_;
  const int64_t sender_;
  std::atomic<int64_t> seq_{0};
};

}  // namespace viscera::client
