#include "client/driver.h"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <map>

#include <viscera_proto/force_feedback_t.hpp>
#include <viscera_proto/tool_pose_t.hpp>

#include "bus/channels.h"
#include "bus/header.h"
#include "common/clock.h"

namespace viscera::client {
namespace {

void SleepUntil(int64_t monotonic_ns) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(monotonic_ns / 1'000'000'000);
  ts.tv_nsec = static_cast<long>(monotonic_ns % 1'000'000'000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(std::ceil(p * v.size())) - 1);
  std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
  return v[k];
}

}  // namespace

DriveResult Drive(SessionClient& client, const std::vector<Waypoint>& path,
                  const DriveOptions& options) {
  DriveResult r;
  std::vector<double> round_trips;
  std::map<int64_t, Vec3> targets;  // pose seq -> target, for the peak report
  int64_t last_answered = -1;
  double force_sum = 0.0;
  const std::string force_channel = bus::SessionChannel(bus::kForcePrefix, options.session_id);
  const bus::SubscriptionId sub = client.bus().Subscribe<viscera_proto::force_feedback_t>(
      force_channel, [&](const viscera_proto::force_feedback_t& f, int64_t recv_utime) {
        if (f.tool != options.tool || !bus::HeaderProblem(f.header).empty()) return;
        ++r.forces_received;
        const Vec3 force(f.force[0], f.force[1], f.force[2]);
        force_sum += force.norm();
        if (force.norm() > r.max_force_n) {
          r.max_force_n = force.norm();
          r.force_at_max = force;
          r.tip_at_max = Vec3(f.tip[0], f.tip[1], f.tip[2]);
          const auto it = targets.find(f.pose_seq);
          if (it != targets.end()) r.target_at_max = it->second;
        }
        if (f.clamped) ++r.clamped;
        r.last_step = std::max<int64_t>(r.last_step, f.step);
        // the first force message that answers a pose gives its round trip
        if (f.pose_seq > last_answered && f.pose_utime > 0) {
          last_answered = f.pose_seq;
          ++r.poses_answered;
          round_trips.push_back(static_cast<double>(recv_utime - f.pose_utime));
        }
      });

  const std::string pose_channel = bus::SessionChannel(bus::kPosePrefix, options.session_id);
  viscera_proto::tool_pose_t pose{};
  pose.tool = options.tool;
  pose.orientation[0] = 1.0;
  const double span = path.back().t - path.front().t;
  const int64_t period_ns = static_cast<int64_t>(1e9 / options.pose_rate_hz);
  const int64_t n = std::max<int64_t>(1, static_cast<int64_t>(span * options.pose_rate_hz) + 1);
  const int64_t start = MonotonicNanos();
  for (int64_t k = 0; k < n; ++k) {
    SleepUntil(start + k * period_ns);
    const Waypoint w = Sample(path, path.front().t + static_cast<double>(k) / options.pose_rate_hz);
    pose.header = bus::MakeHeader(options.session_id, k);
    pose.header.token = options.token;
    pose.header.token_len = static_cast<int32_t>(options.token.size());
    for (int a = 0; a < 3; ++a) pose.position[a] = w.position(a);
    pose.jaw = w.jaw;
    targets[k] = w.position;
    if (client.bus().Publish(pose_channel, pose)) ++r.poses_sent;
    client.bus().Drain();
  }
  const int64_t settle_end = MonotonicNanos() + static_cast<int64_t>(options.settle_s * 1e9);
  while (MonotonicNanos() < settle_end) client.bus().Pump(10);
  client.bus().Unsubscribe(sub);

  r.duration_s = static_cast<double>(MonotonicNanos() - start) * 1e-9;
  r.mean_force_n = r.forces_received > 0 ? force_sum / static_cast<double>(r.forces_received) : 0.0;
  r.round_trip_p50_us = Percentile(round_trips, 0.5);
  r.round_trip_p99_us = Percentile(round_trips, 0.99);
  r.round_trip_max_us =
      round_trips.empty() ? 0.0 : *std::max_element(round_trips.begin(), round_trips.end());
  return r;
}

nlohmann::ordered_json DriveToJson(const DriveResult& r) {
  auto vec = [](const Vec3& v) { return nlohmann::ordered_json::array({v.x(), v.y(), v.z()}); };
  return {{"poses_sent", r.poses_sent},
          {"forces_received", r.forces_received},
          {"poses_answered", r.poses_answered},
          {"max_force_n", r.max_force_n},
          {"mean_force_n", r.mean_force_n},
          {"force_at_max", vec(r.force_at_max)},
          {"tip_at_max", vec(r.tip_at_max)},
          {"target_at_max", vec(r.target_at_max)},
          {"clamped", r.clamped},
          {"round_trip_p50_us", r.round_trip_p50_us},
          {"round_trip_p99_us", r.round_trip_p99_us},
          {"round_trip_max_us", r.round_trip_max_us},
          {"last_step", r.last_step},
          {"duration_s", r.duration_s}};
}

}  // namespace viscera::client
