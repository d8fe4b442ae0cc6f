/// viscera: the thin command-line client of viscerad. Links the bus and the messages
/// only; every command is a few LCM messages and some printing (client/cli/, a file each).
#include <cstdio>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>

#include "bus/lcm_bus.h"
#include "client/cli/commands.h"
#include "client/token_store.h"

namespace {

namespace cli = viscera::client::cli;

// In the order `viscera --help` lists them.
constexpr cli::Command kCommands[] = {
    {"servers", "List the servers heard on the heartbeat channel",
     "  viscera servers              # who is there, what each holds and why\n"
     "  viscera servers --json\n",
     cli::SetUpServers, cli::RunServers},
    {"create", "Start a session",
     "  viscera create cavity --json                 # the least loaded server with room\n"
     "  viscera create cavity --frame-rate -1        # no frames: costs a step only\n"
     "  viscera create --scene-file my_scene.toml --rate 500\n",
     cli::SetUpCreate, cli::RunCreate},
    {"list", "Status of every session of every server", "  viscera list\n", cli::SetUpList,
     cli::RunList},
    {"status", "Status of a session",
     "  viscera status ID\n  viscera status ID --watch --count 8\n", cli::SetUpStatus,
     cli::RunStatus},
    {"report", "Assessment of a session: handling metrics and target exposure",
     "  viscera report ID\n  viscera report ID --final --json\n", cli::SetUpReport, cli::RunReport},
    {"drive", "Drive a session's tool along a path",
     "  viscera drive ID --gesture clearing\n  viscera drive ID --script scenes/clearing.csv "
     "--pose-rate 500\n",
     cli::SetUpDrive, cli::RunDrive},
    {"haptic", "Run a haptic device loop on a session's tool (docs/haptics.md)",
     "  viscera haptic ID --tool right --device sim --script scenes/clearing.csv\n"
     "  viscera haptic ID --tool right --device sim --script scenes/clearing.csv --realtime "
     "80\n",
     cli::SetUpHaptic, cli::RunHaptic},
    {"camera", "Set a session's laparoscope camera",
     "  viscera camera ID --eye -0.02 -0.14 0.20 --target -0.01 0.01 0.05\n", cli::SetUpCamera,
     cli::RunCamera},
    {"destroy", "Stop a session and close its record", "  viscera destroy ID\n",
     cli::SetUpSessionCommand, cli::RunDestroy},
    {"pause", "Stop stepping a session", "  viscera pause ID\n", cli::SetUpSessionCommand,
     cli::RunPause},
    {"resume", "Step a paused session again", "  viscera resume ID\n", cli::SetUpSessionCommand,
     cli::RunResume},
    {"reset", "Put a session back to its scene's start", "  viscera reset ID\n",
     cli::SetUpSessionCommand, cli::RunReset},
    {"frames", "Save a session's frames as JPEG files",
     "  viscera frames ID --out out/frames --count 5\n", cli::SetUpFrames, cli::RunFrames},
    {"record", "Record a session's frames into a video",
     "  viscera record ID --out out/clip.mp4 --seconds 10\n", cli::SetUpRecord, cli::RunRecord},
    {"view",
     "Show a session in a browser: drawn by the page from its skeleton (WebGL), or the server's "
     "frames",
     "  viscera view ID --http 127.0.0.1:8080\n", cli::SetUpView, cli::RunView},
    {"keygen", "Write a new pre-shared key file (mode 0600)",
     "  viscera keygen psk    # then viscerad --key-file psk, viscera --key-file psk ...\n",
     cli::SetUpKeygen, cli::RunKeygen},
};

// The options every command takes: they belong to `viscera` and are matched there from any
// command (listed once, by viscera --help, rather than in every command's help).
void AddCommonOptions(CLI::App* app, cli::Common* common) {
  app->add_option(
      "--lcm-url", common->lcm_url,
      "LCM URL (default: $LCM_DEFAULT_URL, else " + std::string(viscera::bus::kDefaultUrl) + ")");
  app->add_option("--key-file", common->key_file, "Pre-shared key file (sign and check MACs)");
  app->add_option("--sessions", common->sessions_file, "Where session tokens are kept")
      ->capture_default_str();
  app->add_option("--timeout", common->timeout_s, "Seconds to wait for a server")
      ->check(CLI::Range(0.01, 3600.0))
      ->capture_default_str();
  app->add_flag("--json", common->json, "Print JSON");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"viscera: client of the viscera haptic server"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("viscera ") + VISCERA_VERSION);
  app.fallthrough();
  cli::Common common;
  common.sessions_file = viscera::client::DefaultTokenStorePath();
  AddCommonOptions(&app, &common);
  for (const cli::Command& command : kCommands) {
    CLI::App* cmd = app.add_subcommand(command.name, command.help);
    cmd->footer(std::string("\nExamples:\n") + command.examples +
                "\nCommon options (--lcm-url, --key-file, --sessions, --timeout, --json): "
                "viscera --help");
    command.set_up(cmd, &common);
  }

  CLI11_PARSE(app, argc, argv);
  if (!common.token_hex.empty()) {
    std::fprintf(stderr,
                 "viscera: --token is refused: a command line is readable by every local user "
                 "(/proc/PID/cmdline); put the token in a file (--token-file FILE, mode 0600) or "
                 "in $VISCERA_TOKEN\n");
    return cli::kLocalError;
  }
  try {
    const std::string url = viscera::bus::ResolveUrl(common.lcm_url);
    for (const cli::Command& command : kCommands) {
      if (app.got_subcommand(command.name)) return command.run(url, common);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "viscera: %s\n", e.what());
    return cli::kLocalError;
  }
  return cli::kLocalError;
}
