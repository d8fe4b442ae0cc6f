#pragma once
/// ForceLimiter: the last stage before the device. Caps the force's magnitude (the device's
/// limit) and its rate of change (a step in force is felt as a knock and can excite the
/// device), and turns a non-finite force into zero, reached through the rate limit: never a
/// jump, never a NaN on the amplifier.
///
/// Threading: the device loop's thread only.
#include <cstdint>

#include "common/types.h"

namespace viscera::haptic {

class ForceLimiter {
 public:
  /// @throws InputError unless max_force_n > 0 and max_rate_n_s > 0.
  ForceLimiter(double max_force_n, double max_rate_n_s);

  /// The force to send for `wanted` (N) after `period_s` (s) since the previous one.
  Vec3 Apply(const Vec3& wanted, double period_s);

  const Vec3& last() const { return last_; }
  double max_force_n() const { return max_force_; }
  double max_rate_n_s() const { return max_rate_; }
  int64_t nonfinite() const { return nonfinite_; }        ///< forces that were NaN or infinite
  int64_t clamped() const { return clamped_; }            ///< periods at the force limit
  int64_t rate_limited() const { return rate_limited_; }  ///< periods at the rate limit

 private:
  double max_force_, max_rate_;
  Vec3 last_ = Vec3::Zero();
  int64_t nonfinite_ = 0, clamped_ = 0, rate_limited_ = 0;
};

}  // namespace viscera::haptic
