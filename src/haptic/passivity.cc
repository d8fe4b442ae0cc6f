#include "haptic/passivity.h"

#include <algorithm>

#include "common/check.h"

namespace viscera::haptic {

namespace {
constexpr double kMinSpeedSquared = 1e-12;  // (m/s)^2: below 1 um/s damping cannot dissipate
}  // namespace

PassivityController::PassivityController(bool enabled, double max_damping_n_s_m)
    : enabled_(enabled), max_damping_(max_damping_n_s_m) {
  ThrowUnless(max_damping_n_s_m >= 0.0,
              "passivity controller: max damping must be >= 0 N s/m, got ", max_damping_n_s_m);
}

void PassivityController::Observe(const Vec3& x) {
  if (has_x_ && x.allFinite()) {
    energy_ -= held_.dot(x - x_prev_);
    min_energy_ = std::min(min_energy_, energy_);
  }
  if (x.allFinite()) {
    x_prev_ = x;
    has_x_ = true;
  }
}

Vec3 PassivityController::Control(const Vec3& force, const Vec3& v, double period_s) {
  last_damping_ = 0.0;
  if (!enabled_ || !force.allFinite() || !v.allFinite()) return force;
  const double v2 = v.squaredNorm();
  const double predicted = energy_ - force.dot(v) * period_s;
  if (predicted >= 0.0 || v2 < kMinSpeedSquared) return force;
  const double alpha = std::min(max_damping_, -predicted / (v2 * period_s));
  last_damping_ = alpha;
  dissipated_ += alpha * v2 * period_s;
  ++activations_;
  return force - alpha * v;
}

}  // namespace viscera::haptic
