#pragma once
/// Four doubles side by side in one vector (GCC's vector extension): a segment's 4 Gauss nodes,
/// or 4 entries of a 3x3 block. GCC lowers them to SSE2 pairs in the baseline code and to one
/// AVX register in an AVX clone (avx_clone.h). Each lane does what the scalar code did, product
/// by product and sum by sum in its order (no FMA: -ffp-contract=off; no reassociation), so
/// the numbers are the scalar code's bit for bit.
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "mechanics/block_band.h"

// Returning a 32-byte vector without AVX "changes the ABI": never at a call, all is inlined.
// Left off for the rest of each file that includes this one, on purpose: its own inline lane
// helpers (contact_window.h, stretching_energy.cc) pass V4 by value too.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace viscera::mechanics::lanes {

typedef double V4 __attribute__((vector_size(32)));
typedef long long Mask4 __attribute__((vector_size(32)));
typedef double V2 __attribute__((vector_size(16)));

[[gnu::always_inline]] inline V4 Load4(const double* p) {
  V4 v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}
[[gnu::always_inline]] inline void Store4(double* p, V4 v) { __builtin_memcpy(p, &v, sizeof v); }
[[gnu::always_inline]] inline V4 Splat(double x) { return V4{x, x, x, x}; }

/// Correctly rounded as std::sqrt; sqrtpd, with no errno path (for sums of squares).
[[gnu::always_inline]] inline V4 Sqrt(V4 v) {
#if !defined(__SSE2__)
  return V4{std::sqrt(v[0]), std::sqrt(v[1]), std::sqrt(v[2]),
            std::sqrt(v[3])};  // elsewhere than x86
#else
  const V2 lo = (V2)_mm_sqrt_pd((__m128d)V2{v[0], v[1]});
  const V2 hi = (V2)_mm_sqrt_pd((__m128d)V2{v[2], v[3]});
  return V4{lo[0], lo[1], hi[0], hi[1]};
#endif
}

/// A 3x3 block's 9 column-major entries: 0-3, 4-7 and 8.
struct Block9 {
  V4 lo, mid;
  double last;
};

/// The column-major entries of the symmetric t t^T: (xx, yx, zx, xy), (yy, zy, xz, yz), zz.
[[gnu::always_inline]] inline Block9 OuterSelf(double x, double y, double z) {
  return {V4{x, y, z, x} * V4{x, x, x, y}, V4{y, z, x, y} * V4{y, y, z, z}, z * z};
}

/// s h, entry by entry.
[[gnu::always_inline]] inline Block9 Scaled(double s, const Block9& h) {
  return {Splat(s) * h.lo, Splat(s) * h.mid, s * h.last};
}

/// The identity's column-major entries, as Block9's lanes.
inline constexpr V4 kIdentityLo{1.0, 0.0, 0.0, 0.0};
inline constexpr V4 kIdentityMid{1.0, 0.0, 0.0, 0.0};

/// A(i, j) += h for a symmetric h given by all 9 entries (and so A(j, i) += h): what
/// BlockBand::AddSymmetric(i, j, 1.0, h's Sym3) adds, entry by entry.
/// @pre |i - j| <= 3.
[[gnu::always_inline]] inline void AddBlock(BlockBand* band, int i, int j, const Block9& h) {
  VISCERA_ASSERT(std::abs(i - j) < BlockBand::kWidth);
  double* b = (i <= j ? band->block(i, j - i) : band->block(j, i - j)).data();
  Store4(b, Load4(b) + h.lo);
  Store4(b + 4, Load4(b + 4) + h.mid);
  b[8] += h.last;
}

}  // namespace viscera::mechanics::lanes
