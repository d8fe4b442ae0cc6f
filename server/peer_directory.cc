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
  // forget the silent ones, at most once per max_age_ns (a peer map is small; this is cheap)
  if (now_ns >= next_sweep_ns_ ||
      (peers_.size() >= kMaxPeers && !peers_.contains(heartbeat.server_id))) {
    std::erase_if(peers_,
                  [&](const auto& entry) { return now_ns - entry.second.heard_ns > max_age_ns_; });
    next_sweep_ns_ = now_ns + max_age_ns_;
  }
  if (peers_.size() >= kMaxPeers && !peers_.contains(heartbeat.server_id)) return;
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
