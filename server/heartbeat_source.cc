#include "server/heartbeat_source.h"

#include <ctime>
#include <utility>

#include "bus/header.h"
#include "common/check.h"
#include "server/record_disk.h"

namespace viscera::server {

int64_t ProcessCpuNanos() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

void PutLimits(const ServerConfig& config, viscera_proto::heartbeat_t* heartbeat) {
  heartbeat->max_clock_skew_s = config.max_clock_skew_s;
  heartbeat->session_lease_s = config.session_lease_s;
  heartbeat->max_message_bytes = config.max_message_bytes;
  heartbeat->max_creates_per_minute = config.max_creates_per_minute;
  heartbeat->max_rate_hz = config.max_rate_hz;
  heartbeat->max_frame_mpix_per_s = config.max_frame_mpix_per_s;
  heartbeat->max_control_points = config.max_control_points;
  heartbeat->max_obstacles = config.max_obstacles;
  heartbeat->max_mesh_resolution = config.max_mesh_resolution;
  heartbeat->max_mesh_bytes = config.max_mesh_bytes;
  heartbeat->max_settle_s = config.max_settle_s;
  heartbeat->max_session_load = config.max_session_load;
  heartbeat->max_spheres = config.max_spheres;
  heartbeat->max_margin_radii = config.max_margin_radii;
  heartbeat->max_tools = config.max_tools;
  heartbeat->max_mesh_triangles = config.max_mesh_triangles;
  heartbeat->max_build_s = config.max_build_s;
  heartbeat->record_free_bytes = config.log_dir.empty() ? -1 : FreeBytes(config.log_dir);
  heartbeat->min_record_free_bytes = config.min_record_free_bytes;
}

HeartbeatSource::HeartbeatSource(std::string server_id, int max_sessions, HeartbeatClocks clocks)
    : server_id_(std::move(server_id)),
      max_sessions_(max_sessions),
      clocks_(std::move(clocks)),
      start_wall_ns_(clocks_.wall_ns()),
      last_wall_ns_(start_wall_ns_),
      last_cpu_ns_(clocks_.cpu_ns()) {
  ThrowUnless(!server_id_.empty(), "server id must not be empty");
  ThrowUnless(max_sessions_ >= 1, "max sessions must be >= 1, got ", max_sessions_);
}

void HeartbeatSource::SetMaxSessions(int max_sessions) {
  VISCERA_DEMAND(max_sessions >= 1);
  max_sessions_ = max_sessions;
}

viscera_proto::heartbeat_t HeartbeatSource::Next(int num_sessions, int64_t rejected) {
  VISCERA_DEMAND(num_sessions >= 0 && rejected >= 0);
  const int64_t wall_ns = clocks_.wall_ns();
  const int64_t cpu_ns = clocks_.cpu_ns();
  const int64_t wall_elapsed = wall_ns - last_wall_ns_;

  viscera_proto::heartbeat_t msg;
  msg.header = bus::MakeHeader(/*session_id=*/0, seq_++);
  msg.server_id = server_id_;
  msg.num_sessions = num_sessions;
  msg.max_sessions = max_sessions_;
  // the first heartbeat can come microseconds after start: report 0 rather than noise
  msg.load = wall_elapsed > 1'000'000
                 ? static_cast<float>(static_cast<double>(cpu_ns - last_cpu_ns_) / wall_elapsed)
                 : 0.0f;
  msg.uptime_us = (wall_ns - start_wall_ns_) / 1000;
  msg.rejected = rejected;
  msg.capacity = capacity_note_;
  msg.cores = 0;
  msg.not_ours = 0;
  msg.unconverged_solves = 0;

  last_wall_ns_ = wall_ns;
  last_cpu_ns_ = cpu_ns;
  return msg;
}

}  // namespace viscera::server
