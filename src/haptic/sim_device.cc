#include "haptic/sim_device.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "common/check.h"

namespace viscera::haptic {

namespace {
constexpr double kMaxSubstep = 1e-4;  // s: well under the hand's period (~0.14 s)
}  // namespace

SimDevice::SimDevice(script::ToolScript script, std::string tool, SimHandOptions options)
    : script_(std::move(script)), tool_(std::move(tool)), options_(options) {
  ThrowUnless(script_.Has(tool_), "the tool script has no rows for tool \"", tool_, "\"");
  ThrowUnless(options_.mass_kg > 0 && options_.stiffness_n_m > 0 && options_.damping_n_s_m >= 0 &&
                  options_.limits.damping_n_s_m >= 0,
              "simulated hand: mass ", options_.mass_kg, " kg and stiffness ",
              options_.stiffness_n_m, " N/m must be > 0, dampings >= 0");
  x_ = Target(0.0);
}

DeviceSample SimDevice::Read(double t) {
  // advance the hand from the last read to t with the force held (semi-implicit Euler)
  const double span = std::max(0.0, t - t_);
  const int n = std::max(1, static_cast<int>(std::ceil(span / kMaxSubstep)));
  const double h = span / n;
  const double m = options_.mass_kg, k = options_.stiffness_n_m;
  const double b = options_.damping_n_s_m + options_.limits.damping_n_s_m;
  for (int i = 0; i < n && h > 0.0; ++i) {
    const double ti = t_ + (i + 1) * h;
    const Vec3 pull = k * (Target(ti) - x_) + force_;
    // damping implicit: v+ = (v + h pull / m) / (1 + h b / m)
    v_ = (v_ + h * pull / m) / (1.0 + h * b / m);
    x_ += h * v_;
  }
  t_ = std::max(t_, t);
  const script::ToolKeyframe key = script_.At(tool_, t_);
  DeviceSample s;
  s.position = x_;
  s.orientation = key.orientation;
  s.jaw = key.jaw;
  return s;
}

}  // namespace viscera::haptic
