#include "mechanics/spring_forces.h"

#include <algorithm>

namespace viscera::mechanics {

double AddSpringForces(std::span<const Spring> springs, const Points& q, const Points& qd, Points* F,
                       BlockBand* K, BlockBand* D) {
  double energy = 0.0;
  for (const Spring& sp : springs) {
    const Vec3 x = (q.row(sp.j) - q.row(sp.i)).transpose();
    const double l = x.norm();
    if (l <= 0.0) continue;  // coincident points: no direction to push along
    const Vec3 t = x / l;
    const double stretch = l - sp.rest;
    energy += 0.5 * sp.stiffness * stretch * stretch;
    const double relative_speed = (qd.row(sp.j) - qd.row(sp.i)).dot(t.transpose());
    const Vec3 f = (sp.stiffness * stretch + sp.damping * relative_speed) * t;  // pulls i toward j
    F->row(sp.i) += f.transpose();
    F->row(sp.j) -= f.transpose();
    if (K) {
      const Mat3 ttT = t * t.transpose();
      const double geometric = std::max(0.0, 1.0 - sp.rest / l);
      const Mat3 h = sp.stiffness * (ttT + geometric * (Mat3::Identity() - ttT));
      K->Add(sp.i, sp.i, h);
      K->Add(sp.j, sp.j, h);
      K->Add(sp.i, sp.j, -h);
    }
    if (D && sp.damping > 0.0) {
      const Mat3 h = sp.damping * t * t.transpose();
      D->Add(sp.i, sp.i, h);
      D->Add(sp.j, sp.j, h);
      D->Add(sp.i, sp.j, -h);
    }
  }
  return energy;
}

}  // namespace viscera::mechanics
