#pragma once
/// A contact sphere's window of 4 control points (Interactions::AddForces): its force onto F's
/// 4 rows and its 3x3 stiffness and damping onto K's and D's 10 window blocks, 4 entries per
/// vector (simd_lanes.h: SSE2 pairs in the baseline code, one AVX register in an AVX clone).
/// Each entry gets the products and sums the scalar code gave it, in its order, so the numbers
/// are the scalar code's bit for bit (tests/mechanics/contact_window_test.cc holds them to it).
#include <array>

#include "common/types.h"
#include "mechanics/block_band.h"
#include "mechanics/simd_lanes.h"

namespace viscera::mechanics::contact_window {

/// F's rows first to first + 3 += w[a] f^T (F: a row-major #N by 3 matrix's storage).
/// @pre 0 <= first and first + 3 < N.
[[gnu::always_inline]] inline void AddForce(double* F, int first, const std::array<double, 4>& w,
                                            const Vec3& f) {
  using lanes::Load4, lanes::Store4, lanes::V4;
  double* r = F + 3 * first;  // the window's 12 values, contiguous
  const double x = f.x(), y = f.y(), z = f.z();
  Store4(r, Load4(r) + V4{w[0], w[0], w[0], w[1]} * V4{x, y, z, x});
  Store4(r + 4, Load4(r + 4) + V4{w[1], w[1], w[2], w[2]} * V4{y, z, x, y});
  Store4(r + 8, Load4(r + 8) + V4{w[2], w[3], w[3], w[3]} * V4{z, x, y, z});
}

/// A symmetric block's 9 column-major entries from its Sym3 (xx, yy, zz, xy, xz, yz).
[[gnu::always_inline]] inline lanes::Block9 Full(const Sym3& h) {
  return {lanes::V4{h[0], h[3], h[4], h[3]}, lanes::V4{h[1], h[5], h[4], h[5]}, h[2]};
}

/// K += (w w^T) (x) k on the window's 10 upper blocks from `first`, and D the same with d if
/// given: BlockBand::AddSymmetric(first + a, first + b, w[a] * w[b], k) for a <= b, entry by entry.
/// @pre 0 <= first and first + 3 < K's n (and D's, with d).
[[gnu::always_inline]] inline void AddOuter(int first, const std::array<double, 4>& w,
                                            const Sym3& k, const Sym3* d, BlockBand* K,
                                            BlockBand* D) {
  const lanes::Block9 kf = Full(k);
  const lanes::Block9 df = d ? Full(*d) : lanes::Block9{};
  for (int a = 0; a < 4; ++a) {
    for (int b = a; b < 4; ++b) {
      const double wab = w[a] * w[b];
      lanes::AddBlock(K, first + a, first + b, lanes::Scaled(wab, kf));
      if (d) lanes::AddBlock(D, first + a, first + b, lanes::Scaled(wab, df));
    }
  }
}

}  // namespace viscera::mechanics::contact_window
