#pragma once
// The faults viscera-soak injects into a running viscerad, each over the real bus: what a
// crashing client, a flooding or malicious host and a broken scene do (docs/reliability.md).
#include <sys/types.h>

#include <cstdint>
#include <string>
#include <vector>

#include <viscera_proto/session_reply_t.hpp>

#include "client/session_client.h"

namespace viscera::soak {

struct Created {
  int64_t id = 0;
  std::vector<uint8_t> token;
  std::string refusal;  ///< "" when created
};

/// Creates a session of `scene_name` (or inline `scene_toml`) on `server_id`.
Created CreateSession(client::SessionClient& client, const std::string& server_id,
                      const std::string& scene_name, const std::string& scene_toml,
                      double frame_rate_hz);

/// Destroys a session. @return true when the server said kOk.
bool DestroySession(client::SessionClient& client, const Created& session);

/// `count` valid poses of tool 0 as fast as the bus takes them (one sender, rising sequence).
void FloodPoses(bus::LcmBus& bus, const Created& session, int count);

/// Garbage, truncated and wrongly typed datagrams on the request and pose channels.
/// @return datagrams sent.
int SendMalformed(bus::LcmBus& bus, int64_t session_id, uint32_t seed);

/// A create whose datagram exceeds `max_bytes`: @return the server's reply message ("" if none).
std::string SendOversize(client::SessionClient& client, const std::string& server_id,
                         int max_bytes);

/// Creates with broken or hostile inline scenes. @return how many were refused with a reason.
int SendMalformedScenes(client::SessionClient& client, const std::string& server_id);

/// An inline scene that blows up (RK4 far beyond its stability limit): the session recovers.
std::string UnstableScene();

/// Starts `viscera drive ID --gesture ...` as a child process (the client to kill).
pid_t StartDriver(const std::string& viscera, const std::string& url, int64_t id,
                  const std::vector<uint8_t>& token, const std::string& script);

/// RSS (kB) and thread count of a process, from /proc/PID/status (-1 if gone).
struct ProcessFigures {
  int64_t rss_kb = -1;
  int threads = -1;
};
ProcessFigures Figures(pid_t pid);

}  // namespace viscera::soak
