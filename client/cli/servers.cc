// viscera servers: the servers heard on the heartbeat channel.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>

#include <viscera_proto/heartbeat_t.hpp>

#include "bus/channels.h"
#include "bus/lcm_bus.h"
#include "client/cli/commands.h"
#include "client/server_directory.h"

namespace viscera::client::cli {

void SetUpServers(CLI::App* cmd, Common* common) {
  (void)cmd;
  (void)common;
}

int RunServers(const std::string& url, const Common& c) {
  bus::LcmBus bus(url);
  bus.SetAuth(LoadAuth(c));
  ServerDirectory directory;
  bus.Subscribe<viscera_proto::heartbeat_t>(
      bus::kHeartbeatChannel,
      [&](const viscera_proto::heartbeat_t& msg, int64_t) { directory.Observe(msg); });

  // Listen for the whole timeout: every server beats once a second, so a timeout of
  // a little over a second hears each of them at least once.
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(c.timeout_s));
  for (auto now = Clock::now(); now < deadline; now = Clock::now()) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now);
    bus.Pump(static_cast<int>(std::max<int64_t>(left.count(), 1)));
  }

  if (directory.rejected() > 0) {
    std::fprintf(stderr, "viscera: ignored %lld heartbeat(s): %s\n",
                 static_cast<long long>(directory.rejected()), directory.last_rejection().c_str());
  }
  if (bus.stats().decode_failures > 0) {
    std::fprintf(stderr, "viscera: %lld malformed message(s) on %s\n",
                 static_cast<long long>(bus.stats().decode_failures), bus::kHeartbeatChannel);
  }
  const auto servers = directory.Servers();
  if (servers.empty()) {
    std::fprintf(stderr,
                 "viscera: no server answered on %s within %g s (is viscerad running? "
                 "for udpm://, does this network have a multicast route?)\n",
                 url.c_str(), c.timeout_s);
    return kNoServer;
  }
  if (c.json) {
    std::cout << ServersToJson(servers).dump(2) << "\n";
  } else {
    std::cout << ServersToTable(servers);
  }
  return 0;
}

}  // namespace viscera::client::cli
