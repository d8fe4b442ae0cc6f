#pragma once
/// The options of `viscera haptic` (CLI11), kept beside the command they configure.
#include <CLI/CLI.hpp>

#include "client/haptic_command.h"

namespace viscera::client {

/// What the command line sets beyond HapticCommand, in the units people type (ms, mm, us).
struct HapticCli {
  HapticCommand command;
  double delay_ms = 0.0, jitter_ms = 0.0, stale_ms = 250.0, fade_ms = 150.0, spin_us = -1.0;
  double deadband_mm = 0.0;
  bool no_passivity = false, quiet = false;
};

/// Adds the haptic command's options (all but the common ones and --token) to `cmd`.
inline void AddHapticOptions(CLI::App* cmd, HapticCli* o) {
  HapticCommand& h = o->command;
  cmd->add_option("id", h.session_id, "Session id")->required();
  cmd->add_option("--tool", h.tool_name, "Tool of the session to drive and feel")->required();
  cmd->add_option("--device", h.device,
                  "Device backend: sim (a simulated hand) or replay (a --log)")
      ->capture_default_str();
  cmd->add_option("--script", h.script, "sim: the hand's intended path (tool script CSV)");
  cmd->add_option("--replay", h.replay_log, "replay: positions from this --log JSONL file");
  cmd->add_option("--seconds", h.loop.seconds,
                  "Run time (s; default: the script's or log's length)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--rate", h.loop.rate_hz, "Device loop rate (Hz)")
      ->check(CLI::Range(10.0, 20000.0))
      ->capture_default_str();
  cmd->add_option("--log", h.log_path, "One JSON line per device period (t, position, force, ...)");
  cmd->add_option("--delay-ms", o->delay_ms, "Impairment: one-way delay each way (ms)")
      ->check(CLI::Range(0.0, 10000.0));
  cmd->add_option("--jitter-ms", o->jitter_ms, "Impairment: +- uniform jitter (ms)")
      ->check(CLI::Range(0.0, 10000.0));
  cmd->add_option("--loss", h.loop.impairment.loss, "Impairment: fraction of messages lost (0..1)")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--seed", h.loop.impairment.seed, "Impairment: random seed")
      ->capture_default_str();
  cmd->add_option("--max-force", h.loop.max_force_n, "Force limit (N; default: the device's)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--max-force-rate", h.loop.max_force_rate_n_s, "Force-rate limit (N/s)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--crossfade", h.loop.model.crossfade_periods,
                  "Periods over which a new answer takes over")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd->add_option("--stale-ms", o->stale_ms, "Fade the force once the model is this old (ms)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--fade-ms", o->fade_ms, "Length of the stale fade (ms)")
      ->check(CLI::Range(1.0, 100000.0))
      ->capture_default_str();
  cmd->add_option("--deadband-mm", o->deadband_mm,
                  "Publish the pose only when it moved more than this (mm; 0: every period)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--no-passivity", o->no_passivity,
                "Passivity controller off (the observer still reports energy)");
  cmd->add_option("--spin-us", o->spin_us,
                  "Pacing: spin this long before each deadline (us; -1 = 50 with --realtime "
                  "granted, else 0)")
      ->check(CLI::Range(-1.0, 100000.0))
      ->capture_default_str();
  cmd->add_option("--realtime", h.loop.realtime_priority,
                  "SCHED_FIFO priority of the loop thread (0: off; refused in user namespaces)")
      ->check(CLI::Range(0, 99));
  cmd->add_option("--hand-stiffness", h.hand.stiffness_n_m, "sim: the hand's grip stiffness (N/m)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--device-max-force", h.hand.limits.max_force_n,
                  "sim/replay: the device's force limit (N)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_flag("--quiet", o->quiet, "No live report on the terminal");
}

}  // namespace viscera::client
