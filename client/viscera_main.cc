/// viscera: the thin command-line client of viscerad. Links the bus and the messages
/// only; every command is a few LCM messages and some printing.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "bus/channels.h"
#include "bus/lcm_bus.h"
#include "client/server_directory.h"

namespace {

// Exit codes: 0 success, 1 local error (bad URL, no multicast route), 2 no server
// answered; CLI11 reports bad flags with its own codes (100 and up).
constexpr int kNoServer = 2;

struct ServersOptions {
  double timeout_s = 2.0;
  bool json = false;
};

int RunServers(const std::string& url, const ServersOptions& options) {
  viscera::bus::LcmBus bus(url);
  viscera::client::ServerDirectory directory;
  bus.Subscribe<viscera_proto::heartbeat_t>(
      viscera::bus::kHeartbeatChannel,
      [&](const viscera_proto::heartbeat_t& msg, int64_t) { directory.Observe(msg); });

  // Listen for the whole timeout: every server beats once a second, so a timeout of
  // a little over a second hears each of them at least once.
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(options.timeout_s));
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
                 static_cast<long long>(bus.stats().decode_failures), viscera::bus::kHeartbeatChannel);
  }
  const auto servers = directory.Servers();
  if (servers.empty()) {
    std::fprintf(stderr,
                 "viscera: no server answered on %s within %g s (is viscerad running? "
                 "for udpm://, does this network have a multicast route?)\n",
                 url.c_str(), options.timeout_s);
    return kNoServer;
  }
  if (options.json) {
    std::cout << viscera::client::ServersToJson(servers).dump(2) << "\n";
  } else {
    std::cout << viscera::client::ServersToTable(servers);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"viscera: client of the viscera haptic server"};
  app.require_subcommand(1);
  std::string lcm_url;
  app.add_option("--lcm-url", lcm_url,
                 "LCM URL (default: $LCM_DEFAULT_URL, else " + std::string(viscera::bus::kDefaultUrl) + ")");

  ServersOptions servers_options;
  CLI::App* servers = app.add_subcommand("servers", "List the servers heard on the heartbeat channel");
  servers->add_option("--timeout", servers_options.timeout_s, "Seconds to listen")
      ->check(CLI::Range(0.01, 3600.0))
      ->capture_default_str();
  servers->add_flag("--json", servers_options.json, "Print a JSON array");
  // accept --lcm-url after the subcommand too, as scripts tend to put it there
  servers->add_option("--lcm-url", lcm_url, "LCM URL");

  CLI11_PARSE(app, argc, argv);
  try {
    const std::string url = viscera::bus::ResolveUrl(lcm_url);
    if (servers->parsed()) return RunServers(url, servers_options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "viscera: %s\n", e.what());
    return 1;
  }
  return 1;
}
