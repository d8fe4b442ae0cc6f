#include "mechanics/spring_forces.h"

#include "mechanics/avx_clone.h"
#include "mechanics/simd_lanes.h"

#include <algorithm>

namespace viscera::mechanics {

using lanes::Splat;
using lanes::V4;

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
    // Both blocks are symmetric: h on the two diagonal blocks, -h between them. t t^T by its 9
    // column-major entries (the mirrored ones are the same products), 4 per vector.
    const lanes::Block9 tt = lanes::OuterSelf(t.x(), t.y(), t.z());
    if (K) {
      // k (t t^T + g (I - t t^T)), g the geometric part. Off the diagonal tt + g (0 - tt) is
      // tt - g tt bit for bit (0 - tt is -tt, signed zeros included; a + (-b) is a - b).
      const double geometric = std::max(0.0, 1.0 - sp.rest * inv_l);
      const V4 k = Splat(sp.stiffness), g = Splat(geometric);
      const lanes::Block9 h{k * (tt.lo + g * (lanes::kIdentityLo - tt.lo)), k * (tt.mid + g * (lanes::kIdentityMid - tt.mid)),
                            sp.stiffness * (tt.last + geometric * (1.0 - tt.last))};
      lanes::AddBlock(K, sp.i, sp.i, h);
      lanes::AddBlock(K, sp.j, sp.j, h);
      lanes::AddBlock(K, sp.i, sp.j, lanes::Scaled(-1.0, h));
    }
    if (D && sp.damping > 0.0) {
      // c t t^T once for the three blocks.
      const lanes::Block9 d = lanes::Scaled(sp.damping, tt);
      lanes::AddBlock(D, sp.i, sp.i, d);
      lanes::AddBlock(D, sp.j, sp.j, d);
      lanes::AddBlock(D, sp.i, sp.j, lanes::Scaled(-1.0, d));
    }
  }
  return energy;
}

}  // namespace viscera::mechanics
