#include "server/peer_directory.h"

#include <utility>
#include <vector>

#include "bus/header.h"

namespace viscera::server {

PeerDirectory::PeerDirectory(std::string own_id, int64_t max_age_ns)
    : own_id_(std::move(own_id)), max_age_ns_(max_age_ns) {}

void PeerDirectory::Observe(const viscera_proto::heartbeat_t& heartbeat, int64_t now_ns) {
  if (heartbeat.server_id == own_id_ || heartbeat.server_id.empty() ||
      !bus::HeaderProblem(heartbeat.header).empty()) {
    return;
  }
  Peer& p = peers_[heartbeat.server_id];
  p.load = {heartbeat.server_id, heartbeat.num_sessions, heartbeat.max_sessions, heartbeat.load};
  p.heard_ns = now_ns;
}

std::optional<bus::ServerLoad> PeerDirectory::Suggest(int64_t now_ns) const {
  std::vector<bus::ServerLoad> fresh;
  for (const auto& [id, p] : peers_) {
    if (now_ns - p.heard_ns <= max_age_ns_) fresh.push_back(p.load);
  }
  return bus::PickServer(fresh);
}

}  // namespace viscera::server
