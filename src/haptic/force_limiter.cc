#include "haptic/force_limiter.h"

#include <algorithm>

#include "common/check.h"

namespace viscera::haptic {

ForceLimiter::ForceLimiter(double max_force_n, double max_rate_n_s)
    : max_force_(max_force_n), max_rate_(max_rate_n_s) {
  ThrowUnless(max_force_n > 0.0 && max_rate_n_s > 0.0, "force limits must be > 0: max force ",
              max_force_n, " N, max rate ", max_rate_n_s, " N/s");
}

Vec3 ForceLimiter::Apply(const Vec3& wanted, double period_s) {
  Vec3 f = wanted;
  if (!f.allFinite()) {
    ++nonfinite_;
    f.setZero();
  }
  if (f.norm() > max_force_) {
    ++clamped_;
    f *= max_force_ / f.norm();
  }
  // at most max_rate * period from the last force sent (a period of 0 still allows nothing)
  const double step = max_rate_ * std::max(0.0, period_s);
  const Vec3 change = f - last_;
  if (change.norm() > step) {
    ++rate_limited_;
    f = last_ + change * (step / change.norm());
  }
  last_ = f;
  return f;
}

}  // namespace viscera::haptic
