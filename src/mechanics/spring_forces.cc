#include "mechanics/spring_forces.h"

#include "mechanics/avx_clone.h"

#include <algorithm>

namespace viscera::mechanics {

VISCERA_AVX_CLONE double AddSpringForces(std::span<const Spring> springs, const Points& q, const Points& qd, Points* F,
                       BlockBand* K, BlockBand* D) {
  double energy = 0.0;
  for (const Spring& sp : springs) {
    const Vec3 x = (q.row(sp.j) - q.row(sp.i)).transpose();
    const double l = x.norm();
    if (l <= 0.0) continue;  // coincident points: no direction to push along
    const double inv_l = 1.0 / l;  // one division, not four
    const Vec3 t = x * inv_l;
    const double stretch = l - sp.rest;
    energy += 0.5 * sp.stiffness * stretch * stretch;
    const double relative_speed = (qd.row(sp.j) - qd.row(sp.i)).dot(t.transpose());
    const Vec3 f = (sp.stiffness * stretch + sp.damping * relative_speed) * t;  // pulls i toward j
    F->row(sp.i) += f.transpose();
    F->row(sp.j) -= f.transpose();
    if (!K && !(D && sp.damping > 0.0)) continue;  // forces only (RK4, energies)
    // Both blocks are symmetric: h on the two diagonal blocks, -h between them.
    const Sym3 ttT{t.x() * t.x(), t.y() * t.y(), t.z() * t.z(), t.x() * t.y(), t.x() * t.z(), t.y() * t.z()};
    if (K) {
      // k (t t^T + g (I - t t^T)), g the geometric part.
      const double geometric = std::max(0.0, 1.0 - sp.rest * inv_l);
      const double k = sp.stiffness, g = geometric;
      const Sym3 h{k * (ttT[0] + g * (1.0 - ttT[0])), k * (ttT[1] + g * (1.0 - ttT[1])), k * (ttT[2] + g * (1.0 - ttT[2])),
                   k * (ttT[3] - g * ttT[3]),         k * (ttT[4] - g * ttT[4]),         k * (ttT[5] - g * ttT[5])};
      K->AddSymmetric(sp.i, sp.i, 1.0, h);
      K->AddSymmetric(sp.j, sp.j, 1.0, h);
      K->AddSymmetric(sp.i, sp.j, -1.0, h);
    }
    if (D && sp.damping > 0.0) {
      // c ttT once for the three blocks: (-c) x is -(c x) bit for bit.
      const double c = sp.damping;
      const Sym3 d{c * ttT[0], c * ttT[1], c * ttT[2], c * ttT[3], c * ttT[4], c * ttT[5]};
      D->AddSymmetric(sp.i, sp.i, 1.0, d);
      D->AddSymmetric(sp.j, sp.j, 1.0, d);
      D->AddSymmetric(sp.i, sp.j, -1.0, d);
    }
  }
  return energy;
}

}  // namespace viscera::mechanics
