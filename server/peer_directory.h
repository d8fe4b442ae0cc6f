#pragma once
/// PeerDirectory: the other servers on the bus, from their heartbeats, so that a full
/// server can name one that has room when it refuses a create. Bounded: peers not heard for
/// max_age_ns are forgotten, and at most kMaxPeers are kept (heartbeats with ever-new server
/// ids grew the directory by 241 MB in 10 s).
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include <viscera_proto/heartbeat_t.hpp>

#include "bus/placement.h"

namespace viscera::server {

class PeerDirectory {
 public:
  /// Peers kept at most; a new one beyond it is ignored until an old one expires.
  static constexpr size_t kMaxPeers = 256;

  /// @param own_id this server's id: its own heartbeats are not a peer's.
  /// @param max_age_ns a peer not heard for longer is forgotten (gone or unreachable).
  PeerDirectory(std::string own_id, int64_t max_age_ns);

  /// Records a heartbeat received at `now_ns` (monotonic); ignores our own and broken ones.
  void Observe(const viscera_proto::heartbeat_t& heartbeat, int64_t now_ns);

  /// The peer a new session should go to (bus::PickServer over peers heard within
  /// max_age_ns of `now_ns`), or none.
  std::optional<bus::ServerLoad> Suggest(int64_t now_ns) const;

  size_t size() const { return peers_.size(); }

 private:
  struct Peer {
    bus::ServerLoad load;
    int64_t heard_ns = 0;
  };
  std::string own_id_;
  int64_t max_age_ns_;
  std::map<std::string, Peer> peers_;
  int64_t next_sweep_ns_ = 0;
};

}  // namespace viscera::server
