// viscera report: the session's assessment (docs/assessment.md) from its status: now, or with
// --final the one its last status carries when it ends (the same as the JSON the server writes
// by its record).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>

#include "assessment/status_report.h"
#include "bus/channels.h"
#include "client/cli/commands.h"

namespace viscera::client::cli {

namespace {

int64_t report_id = 0;
bool report_final = false;

}  // namespace

void SetUpReport(CLI::App* cmd, Common* common) {
  (void)common;
  cmd->add_option("id", report_id, "Session id")->required();
  cmd->add_flag("--final", report_final,
                "Wait for the session to end and print its final assessment");
}

int RunReport(const std::string& url, const Common& c) {
  const int64_t id = report_id;
  SessionClient client(url, LoadAuth(c));
  viscera_proto::session_status_t status;
  if (const int rc = FetchStatus(client, url, c, id, &status); rc != 0) return rc;
  if (report_final) {
    bool ended = false;
    auto last = std::chrono::steady_clock::now();
    client.bus().Subscribe<viscera_proto::session_status_t>(
        bus::SessionChannel(bus::kStatusPrefix, id),
        [&](const viscera_proto::session_status_t& s, int64_t) {
          last = std::chrono::steady_clock::now();
          if (ended) return;
          status = s;
          ended = s.state == viscera_proto::session_status_t::kStopped ||
                  s.state == viscera_proto::session_status_t::kFaulted;
        });
    while (!ended) {
      client.bus().Pump(100);
      if (std::chrono::steady_clock::now() - last >
          std::chrono::duration<double>(std::max(c.timeout_s, 2.0))) {
        std::fprintf(stderr, "viscera: session %lld went silent before it ended\n",
                     static_cast<long long>(id));
        return kNoServer;
      }
    }
  }
  const assessment::Report report = assessment::ReportFromStatus(status);
  if (c.json) {
    std::cout << assessment::ToJson(report).dump(2) << "\n";
  } else {
    std::cout << assessment::FormatReport(report);
  }
  return 0;
}

}  // namespace viscera::client::cli
