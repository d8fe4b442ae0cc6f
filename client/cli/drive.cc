// viscera drive: drives a session's tool along a tool script and sums up what it felt.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <optional>

#include "client/cli/commands.h"
#include "client/driver.h"
#include "client/gesture.h"
#include "client/keep_alive.h"
#include "client/status_format.h"

namespace viscera::client::cli {

using viscera_proto::session_request_t;

namespace {

struct DriveCli {
  int64_t id = 0;
  std::string script;
  std::string gesture;
  double pose_rate_hz = 100.0;
};

DriveCli options;

}  // namespace

void SetUpDrive(CLI::App* cmd, Common* common) {
  cmd->add_option("id", options.id, "Session id")->required();
  cmd->add_option("--script", options.script,
                  "Tool script (CSV t,tool,x,y,z,qw,qx,qy,qz,jaw; scenes/clearing.csv)");
  cmd->add_option("--gesture", options.gesture, "Built-in gesture: clearing");
  cmd->add_option("--pose-rate", options.pose_rate_hz, "Poses per second")
      ->check(CLI::Range(1.0, 10000.0))
      ->capture_default_str();
  AddTokenOptions(cmd, common);
}

int RunDrive(const std::string& url, const Common& c) {
  const DriveCli& o = options;
  if (o.script.empty() == o.gesture.empty()) {
    std::fprintf(stderr, "viscera: drive needs --script FILE or --gesture clearing\n");
    return kLocalError;
  }
  if (!o.gesture.empty() && o.gesture != "clearing") {
    std::fprintf(stderr, "viscera: unknown gesture '%s' (known: clearing)\n", o.gesture.c_str());
    return kLocalError;
  }
  const script::ToolScript script = o.script.empty() ? ClearingGesture() : LoadScript(o.script);
  SessionClient client(url, LoadAuth(c));
  // the session must exist and have the tool
  viscera_proto::session_status_t status;
  if (const int rc = FetchStatus(client, url, c, o.id, &status); rc != 0) return rc;
  DriveOptions drive;
  drive.session_id = o.id;
  drive.token = TokenFor(c, o.id, nullptr);
  drive.tool_names = status.tool_names;
  drive.pose_rate_hz = o.pose_rate_hz;
  for (const std::string& name : script.tools()) {
    if (std::find(drive.tool_names.begin(), drive.tool_names.end(), name) ==
        drive.tool_names.end()) {
      std::fprintf(
          stderr, "viscera: the script drives tool \"%s\" but session %lld has %s\n", name.c_str(),
          static_cast<long long>(o.id),
          drive.tool_names.empty() ? "no tools (its scene has no [[tool]])" : "other tools");
      return kRefused;
    }
  }
  // poses renew the lease too; the keep-alive covers pauses in a script
  std::optional<KeepAlive> keep_alive;
  keep_alive.emplace(&client, o.id, drive.token, KeepAlivePeriod(status.lease_s));
  const DriveResult r = Drive(client, script, drive);
  keep_alive.reset();
  const auto after = client.Request(MakeRequest(session_request_t::kStatus, o.id), c.timeout_s);
  if (after.empty() || after.front().num_sessions < 1)
    return NoServer(c, url, "the status request");
  const auto& s = after.front().sessions[0];
  if (s.replayed > status.replayed) {
    std::fprintf(stderr,
                 "viscera: session %lld refused %lld messages as replayed or stale while driving "
                 "(last: %s)\n",
                 static_cast<long long>(o.id), static_cast<long long>(s.replayed - status.replayed),
                 s.last_error.c_str());
  }
  if (c.json) {
    std::cout
        << Json{{"session", o.id}, {"drive", DriveToJson(r)}, {"status", StatusToJson(s)}}.dump(2)
        << "\n";
  } else {
    std::printf("drove session %lld for %.2f s: %lld poses sent at %g Hz, %lld forces received\n",
                static_cast<long long>(o.id), r.duration_s, static_cast<long long>(r.poses_sent),
                o.pose_rate_hz, static_cast<long long>(r.forces_received));
    std::printf(
        "force      max |F| %.3f N on %s (%.3f, %.3f, %.3f), mean |F| %.3f N, clamped %lld\n",
        r.max_force_n, r.tool_at_max.c_str(), r.force_at_max.x(), r.force_at_max.y(),
        r.force_at_max.z(), r.mean_force_n, static_cast<long long>(r.clamped));
    std::printf(
        "round trip pose -> force p50 %.0f us, p99 %.0f us, max %.0f us (%lld poses answered)\n",
        r.round_trip_p50_us, r.round_trip_p99_us, r.round_trip_max_us,
        static_cast<long long>(r.poses_answered));
    if (r.reaches > 0)
      std::printf("script     %d grasps reached again, %.2f s behind its clock\n", r.reaches,
                  r.script_delay_s);
    std::printf(
        "mechanics  %.0f of %.0f Hz, %lld deadline %s, step p50 %.0f us p99 %.0f us, "
        "jitter p99 %.0f us, %lld rejected\n",
        s.achieved_rate_hz, s.rate_hz, static_cast<long long>(s.deadline_misses),
        s.deadline_misses == 1 ? "miss" : "misses", s.step_cost_p50_us, s.step_cost_p99_us,
        s.jitter_p99_us, static_cast<long long>(s.rejected));
  }
  if (r.forces_received == 0) {
    std::fprintf(stderr, "viscera: no force feedback received\n");
    return kNoServer;
  }
  return 0;
}

}  // namespace viscera::client::cli
