// viscera haptic: a haptic device loop on a session's tool (docs/haptics.md).
#include <algorithm>
#include <cstdio>

#include <unistd.h>

#include "client/cli/commands.h"
#include "client/haptic_cli.h"
#include "client/haptic_command.h"

namespace viscera::client::cli {

namespace {

HapticCli options;

}  // namespace

void SetUpHaptic(CLI::App* cmd, Common* common) {
  AddHapticOptions(cmd, &options);
  AddTokenOptions(cmd, common);
}

int RunHaptic(const std::string& url, const Common& c) {
  HapticCli o = options;
  HapticCommand& h = o.command;
  SessionClient client(url, LoadAuth(c));
  // the session must exist and have the tool
  viscera_proto::session_status_t status;
  if (const int rc = FetchStatus(client, url, c, h.session_id, &status); rc != 0) return rc;
  const auto it = std::find(status.tool_names.begin(), status.tool_names.end(), h.tool_name);
  if (it == status.tool_names.end()) {
    std::fprintf(stderr, "viscera: session %lld has no tool \"%s\"\n",
                 static_cast<long long>(h.session_id), h.tool_name.c_str());
    return kRefused;
  }
  h.tool = static_cast<int>(it - status.tool_names.begin());
  h.token = TokenFor(c, h.session_id, nullptr);
  h.json = c.json;
  h.live = !c.json && !o.quiet && isatty(STDERR_FILENO) == 1;
  h.loop.impairment.delay_s = o.delay_ms * 1e-3;
  h.loop.impairment.jitter_s = o.jitter_ms * 1e-3;
  h.loop.model.stale_after_s = o.stale_ms * 1e-3;
  h.loop.model.fade_s = o.fade_ms * 1e-3;
  h.loop.spin_ns = o.spin_us < 0.0 ? -1 : static_cast<int64_t>(o.spin_us * 1e3);
  h.loop.deadband_m = o.deadband_mm * 1e-3;
  h.loop.passivity = !o.no_passivity;
  return viscera::client::RunHaptic(client, h);
}

}  // namespace viscera::client::cli
