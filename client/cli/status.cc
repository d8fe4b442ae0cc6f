// viscera status: one session's status, once or (--watch) as the session publishes it.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>

#include "bus/channels.h"
#include "client/cli/commands.h"
#include "client/status_format.h"

namespace viscera::client::cli {

namespace {

struct StatusOptions {
  int64_t id = 0;
  bool watch = false;
  int count = 0;
};

StatusOptions options;

void PrintStatus(const Common& c, const viscera_proto::session_status_t& s) {
  if (c.json) {
    std::cout << StatusToJson(s).dump(c.json ? -1 : 2) << std::endl;
  } else {
    std::cout << StatusTable({s}) << std::flush;
  }
}

}  // namespace

void SetUpStatus(CLI::App* cmd, Common* common) {
  (void)common;
  cmd->add_option("id", options.id, "Session id")->required();
  cmd->add_flag("--watch", options.watch, "Print every status until the session stops");
  cmd->add_option("--count", options.count, "With --watch: stop after N statuses");
}

int RunStatus(const std::string& url, const Common& c) {
  const StatusOptions& o = options;
  SessionClient client(url, LoadAuth(c));
  viscera_proto::session_status_t status;
  if (const int rc = FetchStatus(client, url, c, o.id, &status); rc != 0) return rc;
  if (!o.watch) {
    const Json j = StatusToJson(status);
    if (c.json) {
      std::cout << j.dump(2) << "\n";
    } else {
      std::cout << StatusTable({status});
    }
    return 0;
  }
  // --watch: every status the session publishes, one line (or JSON object) each
  PrintStatus(c, status);
  int printed = 1;
  bool stopped = false;
  client.bus().Subscribe<viscera_proto::session_status_t>(
      bus::SessionChannel(bus::kStatusPrefix, o.id),
      [&](const viscera_proto::session_status_t& s, int64_t) {
        PrintStatus(c, s);
        ++printed;
        if (s.state == viscera_proto::session_status_t::kStopped) stopped = true;
      });
  auto last = std::chrono::steady_clock::now();
  int last_printed = printed;
  while (!stopped && (o.count <= 0 || printed < o.count)) {
    client.bus().Pump(100);
    const auto now = std::chrono::steady_clock::now();
    if (printed != last_printed) {
      last = now;
      last_printed = printed;
    } else if (now - last > std::chrono::duration<double>(std::max(c.timeout_s, 2.0))) {
      std::fprintf(stderr, "viscera: session %lld went silent\n", static_cast<long long>(o.id));
      return kNoServer;
    }
  }
  return 0;
}

}  // namespace viscera::client::cli
