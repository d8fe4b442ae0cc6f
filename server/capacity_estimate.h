#pragma once
/// How many sessions this machine holds: viscerad's default --max-sessions. Measured at
/// start-up, not assumed: the reference scene is stepped on this machine (and, when the
/// server streams frames by default, a few of its frames are drawn), and the cost of one
/// session in cores is compared with the cores this process may run on.
#include <functional>
#include <stdexcept>
#include <string>

#include "server/server_config.h"

namespace viscera::server {

/// Share of the cores sessions may use; the rest is headroom for the I/O thread, LCM's
/// receive thread and wake-up jitter (docs/capacity.md: misses start near 80 % busy).
inline constexpr double kCoreBudget = 0.7;

/// What a session costs is charged per session: its steps always, its frames only when it
/// streams them (at its own rate and size). max_sessions counts sessions without frames.
struct CapacityEstimate {
  std::string scene;           ///< reference scene measured
  int cores = 1;               ///< CPUs this process may run on (its affinity mask)
  double rate_hz = 0.0;        ///< mechanics rate of a session (Hz)
  double step_cpu_us = 0.0;    ///< median CPU time of one step (us)
  double frame_rate_hz = 0.0;  ///< default frame rate (Hz); 0 without frames
  double frame_cpu_ms =
      0.0;              ///< median CPU time of one frame: skin, draw, JPEG (ms); 0: not measured
  int frame_width = 0;  ///< size of the frames measured (pixels)
  int frame_height = 0;
  double session_cores = 0.0;  ///< cost of one session without frames (cores): its steps per second
  int max_sessions = 1;        ///< floor(cores * kCoreBudget / session_cores), at least 1

  /// Cores sessions may use: cores * kCoreBudget.
  double BudgetCores() const;
  /// Cores a frame stream of `rate_hz` (<= 0: none) at width x height adds to a session:
  /// the measured frame's CPU time scaled by the rate and the pixel count (0 when frames
  /// were not measured: then only the count limits sessions).
  double FrameCores(double rate_hz, int width, int height) const;
  /// Cores one session costs: session_cores plus FrameCores.
  double SessionCores(double frame_rate_hz, int width, int height) const;
  /// One line for the start-up message and the heartbeat: what a session costs, with and
  /// without frames, and the cores that hold them.
  std::string Describe() const;
};

/// CPUs in this process's affinity mask (what taskset or a container grants), at least 1.
int AvailableCores();

/// Sessions of `session_cores` each that fit in `cores` at kCoreBudget (at least 1, at
/// most 1024). @pre session_cores > 0.
int SessionsThatFit(int cores, double session_cores);

/// Thrown by EstimateCapacity when its `stop` turned true.
class MeasurementStopped : public std::runtime_error {
 public:
  MeasurementStopped() : std::runtime_error("capacity measurement stopped") {}
};

/// Measures `scene_name` from config.scene_dir at config.rate_hz (0: the scene's rate) for
/// about `seconds` of stepping, plus a few frames of config's default frames when
/// config.frame_rate_hz > 0 (on a thread of its own: an OSMesa context belongs to one).
/// `stop`, when set, is asked before and after loading the scene, before every step and before
/// every frame (from the render thread too): a stopping server abandons a measurement that a
/// busy machine stretches to minutes (loading the scene itself cannot be interrupted).
/// @throws InputError when the scene cannot be loaded; std::runtime_error when OSMesa fails;
///         MeasurementStopped once `stop` returns true.
CapacityEstimate EstimateCapacity(const ServerConfig& config, const std::string& scene_name,
                                  double seconds = 0.3,
                                  const std::function<bool()>& stop = nullptr);

}  // namespace viscera::server
