#include "mechanics/contact_impulses.h"

#include <algorithm>
#include <cmath>

namespace viscera::mechanics {
namespace {

constexpr double kSpeedTolerance = 1e-6;  // m/s: a contact's speed this close to its target is met

}  // namespace

int SolveContactImpulses(const MatX& delassus, Eigen::Index count, const VecX& target, double immobile, VecX* lambda,
                         VecX* speed) {
  VecX& l = *lambda;
  VecX& s = *speed;
  l.head(count).setZero();
  for (int sweep = 0; sweep < kMaxContactSweeps; ++sweep) {
    double worst = 0.0;
    for (Eigen::Index i = 0; i < count; ++i) {
      const double gii = delassus(i, i);
      if (!(gii > immobile)) continue;  // pinned in place: nothing to move
      const double next = std::max(0.0, l(i) + (target(i) - s(i)) / gii);
      const double change = next - l(i);
      if (change == 0.0) continue;
      l(i) = next;
      s.head(count) += change * delassus.col(i).head(count);
      worst = std::max(worst, std::abs(change) * gii);
    }
    if (worst < kSpeedTolerance) return sweep + 1;
  }
  return kMaxContactSweeps;
}

}  // namespace viscera::mechanics
