#pragma once
/// PassivityController: a time-domain passivity observer and controller on the device port
/// (Hannaford and Ryu, "Time-domain passivity control of haptic interfaces", IEEE Trans.
/// Robotics and Automation 18(1), 2002).
///
/// Observer: the energy the rendered system has absorbed from the hand since the start,
///   E(n) = - sum_{k<n} F_k . (x_{k+1} - x_k),
/// the exact work of the force as the device holds it over each period (zero-order hold) on the
/// measured displacement. A passive system keeps E >= 0; E < 0 means delay, loss or sampling
/// made the device inject energy.
/// Controller: before force F_n goes out, it predicts E after the coming period with the
/// current velocity v_n, and when that would be negative adds the damping
///   alpha = -E_pred / (|v_n|^2 T),  F_n <- F_n - alpha v_n   (alpha <= max_damping)
/// that dissipates exactly the deficit. The observer then counts what really happened, so E
/// is an honest figure even when the prediction or the limits fall short.
///
/// Threading: the device loop's thread only. Allocates nothing.
#include <cstdint>

#include "common/types.h"

namespace viscera::haptic {

class PassivityController {
 public:
  /// @param enabled false: observe only (the controller off, for comparison).
  /// @param max_damping_n_s_m the largest damping the controller adds (N s/m), >= 0.
  PassivityController(bool enabled, double max_damping_n_s_m);

  /// The device is at `x` (m) at the start of a period. Adds the work of the force held over
  /// the previous period to the observer.
  void Observe(const Vec3& x);
  /// The force to send after the controller (N), given the model's `force`, the velocity
  /// `v` (m/s) and the period `period_s`.
  Vec3 Control(const Vec3& force, const Vec3& v, double period_s);
  /// The force actually sent (after the limits): held over the coming period.
  void Commit(const Vec3& sent) { held_ = sent; }

  bool enabled() const { return enabled_; }
  double energy_j() const { return energy_; }            ///< E (J): < 0 is energy created
  double min_energy_j() const { return min_energy_; }    ///< lowest E seen (J)
  double dissipated_j() const { return dissipated_; }    ///< by the added damping (J, predicted)
  int64_t activations() const { return activations_; }   ///< periods with damping added
  double last_damping() const { return last_damping_; }  ///< N s/m

 private:
  bool enabled_;
  double max_damping_;
  bool has_x_ = false;
  Vec3 x_prev_ = Vec3::Zero(), held_ = Vec3::Zero();
  double energy_ = 0.0, min_energy_ = 0.0, dissipated_ = 0.0, last_damping_ = 0.0;
  int64_t activations_ = 0;
};

}  // namespace viscera::haptic
