#include "mechanics/spring_forces.h"

#include "mechanics/avx_clone.h"
#include "mechanics/simd_lanes.h"

#include <algorithm>

namespace viscera::mechanics {

using lanes::Splat;
using lanes::V4;

VISCERA_AVX_CLONE double AddSpringForces(std::span<const Spring> springs, const Points& q,
                                         const Points& qd, Points* F, BlockBand* K, BlockBand* D) {
  double energy = 0.0;
  // The lengths and their inverses first, a chunk of springs at a time, 4 per vector: the
  // square roots and divisions of consecutive springs overlap instead of each spring's
  // waiting on them (the same numbers: sqrt and division are correctly rounded either way).
  constexpr size_t kChunk = 64;
  alignas(32) double length[kChunk], inv_length[kChunk];
  for (size_t start = 0; start < springs.size(); start += kChunk) {
    const size_t count = std::min(kChunk, springs.size() - start);
    for (size_t k = 0; k < count; ++k) {
      const Spring& sp = springs[start + k];
      length[k] = (q.row(sp.j) - q.row(sp.i)).transpose().squaredNorm();  // as Vec3::norm() squares
    }
    for (size_t k = count; k % 4 != 0; ++k) length[k] = 1.0;
    for (size_t k = 0; k < count; k += 4) {
      const V4 l = lanes::Sqrt(lanes::Load4(length + k));
      lanes::Store4(length + k, l);
      lanes::Store4(inv_length + k, Splat(1.0) / l);  // one division per spring, not four
    }
    for (size_t k = 0; k < count; ++k) {
      const Spring& sp = springs[start + k];
      const double l = length[k];
      if (l <= 0.0) continue;  // coincident points: no direction to push along
      const Vec3 x = (q.row(sp.j) - q.row(sp.i)).transpose();
      const double inv_l = inv_length[k];
      const Vec3 t = x * inv_l;
      const double stretch = l - sp.rest;
      energy += 0.5 * sp.stiffness * stretch * stretch;
      const double relative_speed = (qd.row(sp.j) - qd.row(sp.i)).dot(t.transpose());
      const Vec3 f =
          (sp.stiffness * stretch + sp.damping * relative_speed) * t;  // pulls i toward j
      F->row(sp.i) += f.transpose();
      F->row(sp.j) -= f.transpose();
      if (!K && !(D && sp.damping > 0.0)) continue;  // forces only (RK4, energies)
      // Both blocks are symmetric: h on the two diagonal blocks, -h between them. t t^T by its 9
      // column-major entries (the mirrored ones are the same products), 4 per vector.
      const lanes::Block9 tt = lanes::OuterSelf(t.x(), t.y(), t.z());
      if (K) {
        // k (t t^T + g (I - t t^T)), g the geometric part. Off the diagonal tt + g (0 - tt) is
        // tt - g tt bit for bit: 0 - tt is -tt but for tt = +0, where both forms give +0, and
        // a + (-b) is a - b.
        const double geometric = std::max(0.0, 1.0 - sp.rest * inv_l);
        const V4 stiffness = Splat(sp.stiffness), g = Splat(geometric);
        const lanes::Block9 h{stiffness * (tt.lo + g * (lanes::kIdentityLo - tt.lo)),
                              stiffness * (tt.mid + g * (lanes::kIdentityMid - tt.mid)),
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
  }
  return energy;
}

}  // namespace viscera::mechanics
