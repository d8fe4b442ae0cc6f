#include "mechanics/mesentery_forces.h"

#include "mechanics/attachment_forces.h"

#include <algorithm>

namespace viscera::mechanics {

TetherPull TetherPullAt(double e, double d) {
  TetherPull p;
  if (e <= 0.0) return p;
  if (d <= 0.0) {
    p.g = e;
    p.slope = 1.0;
    p.energy = 0.5 * e * e;
  } else if (e <= 2.0 * d) {
    const double r = e / d;
    p.g = e * r * r / 3.0;
    p.slope = r * r;
    p.energy = e * e * r * r / 12.0;
  } else {
    // linear beyond 2 d, with the slope (4) the cubic has there: the stiffness stays bounded
    // (a tether that starts far past its slack pulls hard, but not explosively)
    const double x = e - 2.0 * d;
    p.g = 8.0 * d / 3.0 + 4.0 * x;
    p.slope = 4.0;
    p.energy = 4.0 * d * d / 3.0 + 8.0 * d * x / 3.0 + 2.0 * x * x;
  }
  return p;
}

double AddMesenteryForces(std::span<const Tether> tethers, const Points& q, const Points& qd,
                          Points* F, BlockBand* K, BlockBand* D) {
  double energy = 0.0;
  for (const Tether& tether : tethers) {
    const Vec3 x = Model::Evaluate(tether.at, q) - tether.root;
    const double l = x.norm();
    const double stretch = l - tether.length;
    if (stretch <= 0.0) continue;  // slack: no force, no stiffness
    const Vec3 t = x / l;
    const TetherPull pull = TetherPullAt(stretch, tether.onset);
    energy += tether.stiffness * pull.energy;
    const double taut = tether.onset > 0.0 ? std::min(stretch / tether.onset, 1.0) : 1.0;
    const double c = tether.damping * taut;
    const Vec3 v = Model::Evaluate(tether.at, qd);
    const Vec3 f = -(tether.stiffness * pull.g + c * t.dot(v)) * t;
    for (int a = 0; a < 4; ++a) F->row(tether.at.first + a) += tether.at.w(a) * f.transpose();
    const Mat3 ttT = t * t.transpose();
    if (K) {
      const Mat3 h =
          tether.stiffness * (pull.slope * ttT + (pull.g / l) * (Mat3::Identity() - ttT));
      AddCurvePointOuter(tether.at, h, K);
    }
    if (D && c > 0.0) AddCurvePointOuter(tether.at, c * ttT, D);
  }
  return energy;
}

}  // namespace viscera::mechanics
