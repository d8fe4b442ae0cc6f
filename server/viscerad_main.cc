/// viscerad: the viscera haptic server. For now it announces itself with a heartbeat
/// once a second; sessions come with the protocol issue.
#include <pthread.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <ctime>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>

#include "bus/channels.h"
#include "bus/lcm_bus.h"
#include "server/io_loop.h"

namespace {

std::string DefaultServerId() {
  char host[256] = {};
  if (gethostname(host, sizeof(host) - 1) != 0) host[0] = '\0';
  return std::string("viscerad-") + (host[0] != '\0' ? host : "local") + "-" +
         std::to_string(getpid());
}

const char* SignalName(int signal) { return signal == SIGINT ? "SIGINT" : "SIGTERM"; }

int Run(const viscera::server::ServerConfig& config) {
  // Block SIGINT/SIGTERM in every thread (the I/O thread inherits the mask) and take
  // them synchronously here: no handler, no global flag.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  viscera::server::IoLoop loop(config);
  loop.Start();
  std::fprintf(stderr, "viscerad: server '%s' up on %s (heartbeat on %s, max %d sessions)\n",
               config.server_id.c_str(), config.lcm_url.c_str(), viscera::bus::kHeartbeatChannel,
               config.max_sessions);

  // Wake now and then to notice an I/O thread that died.
  const timespec poll{0, 200'000'000};
  while (true) {
    const int signal = sigtimedwait(&stop_signals, nullptr, &poll);
    if (signal == SIGINT || signal == SIGTERM) {
      std::fprintf(stderr, "viscerad: %s received, stopping\n", SignalName(signal));
      loop.Stop();
      std::fprintf(stderr, "viscerad: stopped cleanly after %lld heartbeats\n",
                   static_cast<long long>(loop.heartbeats_sent()));
      return 0;
    }
    if (loop.failed()) {
      loop.Stop();
      std::fprintf(stderr, "viscerad: I/O thread failed: %s\n", loop.error().c_str());
      return 1;
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"viscerad: the viscera haptic server (small intestine simulation over LCM)"};
  std::string lcm_url;
  viscera::server::ServerConfig config;
  config.server_id = DefaultServerId();
  app.add_option("--lcm-url", lcm_url,
                 "LCM URL (default: $LCM_DEFAULT_URL, else " + std::string(viscera::bus::kDefaultUrl) + ")");
  app.add_option("--server-id", config.server_id, "Name announced in heartbeats")
      ->capture_default_str();
  app.add_option("--max-sessions", config.max_sessions, "Sessions accepted at most")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  config.lcm_url = viscera::bus::ResolveUrl(lcm_url);

  try {
    return Run(config);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "viscerad: %s\n", e.what());
    return 1;
  }
}
