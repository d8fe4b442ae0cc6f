#pragma once
/// SimDevice: a simulated hand holding a device. The hand is a mass-spring-damper pulled
/// toward a target trajectory (a tool script: what the user means to do) and pushed by the
/// rendered force, so the loop is closed as it is with a real hand: a stiff contact stops the
/// hand short of its target, a force that creates energy makes it oscillate.
///
///   m x'' = k_h (x_target(t) - x) - b_h x' - b_d x' + F_rendered
///
/// integrated semi-implicitly in sub-steps of at most 0.1 ms over the real time between reads
/// (the force held meanwhile, as a device's amplifier holds it).
#include <string>

#include "haptic/device.h"
#include "script/tool_script.h"

namespace viscera::haptic {

struct SimHandOptions {
  double mass_kg = 0.15;         ///< hand and device moving mass
  double stiffness_n_m = 300.0;  ///< the hand's grip toward its intended path (a relaxed arm)
  double damping_n_s_m = 8.0;    ///< the hand's damping
  /// The device's (limits.damping_n_s_m is its friction b_d). A discrete damper of alpha is
  /// stable on a mass m at period T while alpha T / m stays well under 1: 50 N s/m on 0.15 kg
  /// at 1 kHz.
  DeviceLimits limits{.max_force_n = 3.0,
                      .max_stiffness_n_m = 800.0,
                      .damping_n_s_m = 0.5,
                      .max_added_damping_n_s_m = 50.0};
};

class SimDevice : public Device {
 public:
  /// Follows `tool` of `script`, starting at rest on its first target.
  /// @throws InputError when the script has no such tool or an option is not positive.
  SimDevice(script::ToolScript script, std::string tool, SimHandOptions options = {});

  DeviceLimits limits() const override { return options_.limits; }
  DeviceSample Read(double t) override;
  void Write(const Vec3& force) override { force_ = force; }
  double duration() const override { return script_.duration(); }
  const char* name() const override { return "sim"; }

  const Vec3& velocity() const { return v_; }
  /// Where the hand means to be at `t` (m).
  Vec3 Target(double t) const { return script_.At(tool_, t).tip; }

 private:
  script::ToolScript script_;
  std::string tool_;
  SimHandOptions options_;
  double t_ = 0.0;
  Vec3 x_, v_ = Vec3::Zero(), force_ = Vec3::Zero();
};

}  // namespace viscera::haptic
