#include "client/driver.h"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <map>

#include <viscera_proto/force_feedback_t.hpp>
#include <viscera_proto/skeleton_state_t.hpp>
#include <viscera_proto/tool_pose_t.hpp>

#include "bus/channels.h"
#include "bus/header.h"
#include "bus/tool_pose.h"
#include "common/check.h"
#include "common/clock.h"
#include "common/quantile.h"
#include "script/script_player.h"

namespace viscera::client {

DriveResult Drive(SessionClient& client, const script::ToolScript& script,
                  const DriveOptions& options) {
  // scripted tool name -> the session's tool index
  std::vector<std::pair<std::string, int>> tools;
  for (const std::string& name : script.tools()) {
    const auto it = std::find(options.tool_names.begin(), options.tool_names.end(), name);
    ThrowUnless(it != options.tool_names.end(), "the script drives tool \"", name,
                "\", which the session's scene does not have");
    tools.emplace_back(name, static_cast<int>(it - options.tool_names.begin()));
  }
  ThrowUnless(!tools.empty(), "the script drives no tool");

  DriveResult r;
  std::vector<double> round_trips;
  std::map<int, int64_t> last_answered;  // tool -> last pose seq answered
  std::map<int64_t, Vec3> targets;       // pose seq -> target, for the peak report
  double force_sum = 0.0;
  std::map<int, Vec3> tips;  // tool -> its simulated tip, from the latest force message
  const std::string force_channel = bus::SessionChannel(bus::kForcePrefix, options.session_id);
  const bus::SubscriptionId sub = client.bus().Subscribe<viscera_proto::force_feedback_t>(
      force_channel, [&](const viscera_proto::force_feedback_t& f, int64_t recv_utime) {
        if (f.header.session_id != options.session_id || !bus::HeaderProblem(f.header).empty())
          return;
        ++r.forces_received;
        if (f.tool >= 0 && static_cast<size_t>(f.tool) < options.tool_names.size())
          tips[f.tool] = Vec3(f.tip[0], f.tip[1], f.tip[2]);
        const Vec3 force(f.force[0], f.force[1], f.force[2]);
        force_sum += force.norm();
        if (force.norm() > r.max_force_n) {
          r.max_force_n = force.norm();
          r.force_at_max = force;
          r.tip_at_max = Vec3(f.tip[0], f.tip[1], f.tip[2]);
          if (f.tool >= 0 && static_cast<size_t>(f.tool) < options.tool_names.size()) {
            r.tool_at_max = options.tool_names[static_cast<size_t>(f.tool)];
          }
          const auto it = targets.find(f.pose_seq);
          if (it != targets.end()) r.target_at_max = it->second;
        }
        if (f.clamped) ++r.clamped;
        r.last_step = std::max<int64_t>(r.last_step, f.step);
        // the first force message that answers a pose gives its round trip
        auto [it, fresh] = last_answered.try_emplace(f.tool, -1);
        if (f.pose_seq > it->second && f.pose_utime > 0) {
          it->second = f.pose_seq;
          ++r.poses_answered;
          round_trips.push_back(static_cast<double>(recv_utime - f.pose_utime));
        }
      });

  // Rows aimed at the tube aim at its centre line through the newest skeleton's spheres.
  script::Tube tube;
  bus::SubscriptionId skeleton_sub{};
  if (script.aims_at_tube()) {
    skeleton_sub = client.bus().Subscribe<viscera_proto::skeleton_state_t>(
        bus::SessionChannel(bus::kSkeletonPrefix, options.session_id),
        [&](const viscera_proto::skeleton_state_t& s, int64_t) {
          if (s.header.session_id != options.session_id || !bus::HeaderProblem(s.header).empty())
            return;
          tube.centre_line.resize(s.spheres.size());
          for (size_t i = 0; i < s.spheres.size(); ++i) {
            tube.centre_line[i] = Vec3(s.spheres[i][0], s.spheres[i][1], s.spheres[i][2]);
          }
          tube.radius = s.sphere_radius;
        });
  }
  const std::string pose_channel = bus::SessionChannel(bus::kPosePrefix, options.session_id);
  viscera_proto::tool_pose_t pose{};
  const int64_t period_ns = static_cast<int64_t>(1e9 / options.pose_rate_hz);
  const int64_t start = MonotonicNanos();
  int64_t seq = 0;
  const int64_t sender = bus::NewSenderId();  // this drive's own sequence (replay protection)
  script::ScriptPlayer player(script);
  // to the script's end, and on while a tool reaches again for a grasp (ScriptPlayer)
  for (int64_t k = 0; k == 0 || !player.Done(static_cast<double>(k - 1) / options.pose_rate_hz);
       ++k) {
    SleepUntil(start + k * period_ns);
    const double t = static_cast<double>(k) / options.pose_rate_hz;
    for (const auto& [name, index] : tools) {
      const auto tip = tips.find(index);
      const script::ToolKeyframe key =
          player.At(name, t, tube, tip == tips.end() ? nullptr : &tip->second);
      bus::FillToolPose(options.session_id, seq, options.token, index, key.tip, key.orientation,
                        key.jaw, &pose);
      pose.header.sender = sender;
      if (targets.size() < 1'000'000) targets[seq] = key.tip;
      ++seq;
      if (client.bus().Publish(pose_channel, pose)) ++r.poses_sent;
    }
    client.bus().Drain();
  }
  const int64_t settle_end = MonotonicNanos() + static_cast<int64_t>(options.settle_s * 1e9);
  while (MonotonicNanos() < settle_end) client.bus().Pump(10);
  client.bus().Unsubscribe(sub);
  if (script.aims_at_tube()) client.bus().Unsubscribe(skeleton_sub);

  r.duration_s = static_cast<double>(MonotonicNanos() - start) * 1e-9;
  r.reaches = player.reaches();
  r.script_delay_s = player.delay();
  r.mean_force_n = r.forces_received > 0 ? force_sum / static_cast<double>(r.forces_received) : 0.0;
  r.round_trip_p50_us = Quantile(round_trips, 0.5);
  r.round_trip_p99_us = Quantile(round_trips, 0.99);
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
          {"tool_at_max", r.tool_at_max},
          {"mean_force_n", r.mean_force_n},
          {"force_at_max", vec(r.force_at_max)},
          {"tip_at_max", vec(r.tip_at_max)},
          {"target_at_max", vec(r.target_at_max)},
          {"clamped", r.clamped},
          {"round_trip_p50_us", r.round_trip_p50_us},
          {"round_trip_p99_us", r.round_trip_p99_us},
          {"round_trip_max_us", r.round_trip_max_us},
          {"last_step", r.last_step},
          {"duration_s", r.duration_s},
          {"reaches", r.reaches},
          {"script_delay_s", r.script_delay_s}};
}

}  // namespace viscera::client
