#include "client/server_directory.h"

#include <algorithm>
#include <cstdio>
#include <optional>

#include "bus/header.h"
#include "client/printable.h"

namespace viscera::client {

void ServerDirectory::Observe(const viscera_proto::heartbeat_t& heartbeat) {
  std::string problem = bus::HeaderProblem(heartbeat.header);
  if (problem.empty() && heartbeat.server_id.empty()) problem = "empty server id";
  if (!problem.empty()) {
    ++rejected_;
    last_rejection_ = std::move(problem);
    return;
  }
  ServerInfo& info = servers_[heartbeat.server_id];
  info.server_id = heartbeat.server_id;
  info.sessions = heartbeat.num_sessions;
  info.max_sessions = heartbeat.max_sessions;
  info.load = heartbeat.load;
  info.uptime_s = static_cast<double>(heartbeat.uptime_us) * 1e-6;
  info.rejected = heartbeat.rejected;
  info.record_free_bytes = heartbeat.record_free_bytes;
  info.not_ours = heartbeat.not_ours;
  info.unconverged_solves = heartbeat.unconverged_solves;
  info.cores = heartbeat.cores;
  info.capacity = heartbeat.capacity;
  ++info.heartbeats;
}

std::vector<ServerInfo> ServerDirectory::Servers() const {
  std::vector<ServerInfo> servers;
  servers.reserve(servers_.size());
  for (const auto& [id, info] : servers_) servers.push_back(info);  // std::map: sorted
  return servers;
}

const ServerInfo* PickServer(const std::vector<ServerInfo>& servers) {
  const std::optional<bus::ServerLoad> best =
      bus::PickServer(std::vector<bus::ServerLoad>(servers.begin(), servers.end()));
  if (!best) return nullptr;
  for (const ServerInfo& s : servers) {
    if (s.server_id == best->server_id) return &s;
  }
  return nullptr;
}

std::string ServersSummary(const std::vector<ServerInfo>& servers) {
  std::string out;
  for (const ServerInfo& s : servers) {
    out += (out.empty() ? "" : ", ") + Printable(s.server_id) + " " + std::to_string(s.sessions) +
           "/" + std::to_string(s.max_sessions);
  }
  return out.empty() ? "none" : out;
}

nlohmann::ordered_json ServersToJson(const std::vector<ServerInfo>& servers) {
  nlohmann::ordered_json array = nlohmann::ordered_json::array();
  for (const ServerInfo& s : servers) {
    array.push_back({{"server_id", s.server_id},
                     {"sessions", s.sessions},
                     {"max_sessions", s.max_sessions},
                     {"load", s.load},
                     {"uptime_s", s.uptime_s},
                     {"heartbeats", s.heartbeats},
                     {"rejected", s.rejected},
                     {"record_free_bytes", s.record_free_bytes},
                     {"not_ours", s.not_ours},
                     {"unconverged_solves", s.unconverged_solves},
                     {"cores", s.cores},
                     {"capacity", s.capacity}});
  }
  return array;
}

std::string ServersToTable(const std::vector<ServerInfo>& servers) {
  size_t id_width = std::string("SERVER").size();
  for (const ServerInfo& s : servers) id_width = std::max(id_width, s.server_id.size());
  const int w = static_cast<int>(id_width);
  std::string out;
  char line[512];
  std::snprintf(line, sizeof(line), "%-*s  %8s  %5s  %10s\n", w, "SERVER", "SESSIONS", "LOAD",
                "UPTIME");
  out += line;
  for (const ServerInfo& s : servers) {
    const std::string sessions = std::to_string(s.sessions) + "/" + std::to_string(s.max_sessions);
    std::snprintf(line, sizeof(line), "%-*s  %8s  %4.0f%%  %9.1fs\n", w,
                  Printable(s.server_id).c_str(), sessions.c_str(), 100.0 * s.load, s.uptime_s);
    out += line;
  }
  for (const ServerInfo& s : servers) {
    if (!s.capacity.empty()) out += s.server_id + ": " + s.capacity + "\n";
  }
  return out;
}

}  // namespace viscera::client
