#pragma once
/// Device: what the haptic loop needs of a force-feedback device, and nothing more. A real
/// device SDK (OpenHaptics, Force Dimension's dhd, libnifalcon: docs/haptics.md) is one more
/// implementation of this interface, never a change to the loop.
///
/// Units and frame: metres, newtons and seconds in viscera's world frame (z up). A backend
/// maps its own frame and units (millimetres, a device-centred frame) to these.
///
/// Threading: the device loop's thread calls everything, once per period, Read before Write.
#include <Eigen/Geometry>

#include "common/types.h"

namespace viscera::haptic {

/// What the device can render safely; the loop never asks for more.
struct DeviceLimits {
  double max_force_n = 3.0;        ///< largest force magnitude (N)
  double max_stiffness_n_m = 800;  ///< largest stable rendered stiffness (N/m)
  /// The device's own viscous damping (N s/m): the sampled-spring bound (Colgate) lets a loop
  /// of period T render at most K = 2 b / T.
  double damping_n_s_m = 0.5;
  /// Largest damping the passivity controller may add (N s/m).
  double max_added_damping_n_s_m = 10.0;
};

/// One reading of the device.
struct DeviceSample {
  Vec3 position = Vec3::Zero();                                     ///< tool tip (m, world frame)
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< jaw frame
  double jaw = 1.0;                                                 ///< 0 closed .. 1 open
};

class Device {
 public:
  virtual ~Device() = default;
  virtual DeviceLimits limits() const = 0;
  /// Reads the device at loop time `t` (s since the loop started, non-decreasing).
  virtual DeviceSample Read(double t) = 0;
  /// Commands `force` (N, world frame), held until the next Write. @pre force is finite.
  virtual void Write(const Vec3& force) = 0;
  /// Seconds of motion the backend has to give (a script, a log), or 0 when it has no end.
  virtual double duration() const = 0;
  /// Short name for reports ("sim", "replay").
  virtual const char* name() const = 0;
};

}  // namespace viscera::haptic
