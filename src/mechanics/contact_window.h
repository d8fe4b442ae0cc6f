#pragma once
/// A contact sphere's window of 4 control points (Interactions::AddForces): its force onto F's
/// 4 rows and its 3x3 stiffness and damping onto K's and D's 10 window blocks. Whole rows and
/// blocks go 4 entries per vector (GCC's vector extension: SSE2 pairs in the baseline code, one AVX
/// register in an AVX clone, avx_clone.h); each entry gets the products and sums the scalar code
/// gave it, in its order (no FMA: -ffp-contract=off; no reassociation), so the numbers are the
/// scalar code's bit for bit (tests/mechanics/contact_window_test.cc holds them to it).
#include <array>

#include "common/types.h"
#include "mechanics/block_band.h"

// Returning a 32-byte vector without AVX "changes the ABI": never at a call, all is inlined
// (GCC reports it at the end of the including file, so it stays off there).
#pragma GCC diagnostic ignored "-Wpsabi"

namespace viscera::mechanics::contact_window {

typedef double V4 __attribute__((vector_size(32)));

[[gnu::always_inline]] inline V4 Load4(const double* p) {
  V4 v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}
[[gnu::always_inline]] inline void Store4(double* p, V4 v) { __builtin_memcpy(p, &v, sizeof v); }
[[gnu::always_inline]] inline V4 Splat(double x) { return V4{x, x, x, x}; }

/// A 3x3 block's 9 column-major entries: 0-3, 4-7 and 8.
struct Block9 {
  V4 lo, mid;
  double last;
};

[[gnu::always_inline]] inline void AddTo(const Block9& b, double* m) {
  Store4(m, Load4(m) + b.lo);
  Store4(m + 4, Load4(m + 4) + b.mid);
  m[8] += b.last;
}

/// F's rows first to first + 3 += w[a] f^T (F: a row-major #N by 3 matrix's storage).
/// @pre 0 <= first and first + 3 < N.
[[gnu::always_inline]] inline void AddForce(double* F, int first, const std::array<double, 4>& w, const Vec3& f) {
  double* r = F + 3 * first;  // the window's 12 values, contiguous
  const double x = f.x(), y = f.y(), z = f.z();
  Store4(r, Load4(r) + V4{w[0], w[0], w[0], w[1]} * V4{x, y, z, x});
  Store4(r + 4, Load4(r + 4) + V4{w[1], w[1], w[2], w[2]} * V4{y, z, x, y});
  Store4(r + 8, Load4(r + 8) + V4{w[2], w[3], w[3], w[3]} * V4{z, x, y, z});
}

/// A symmetric block's 9 column-major entries from its Sym3 (xx, yy, zz, xy, xz, yz).
[[gnu::always_inline]] inline Block9 Full(const Sym3& h) {
  return {V4{h[0], h[3], h[4], h[3]}, V4{h[1], h[5], h[4], h[5]}, h[2]};
}

/// K += (w w^T) (x) k on the window's 10 upper blocks from `first`, and D the same with d if
/// given: BlockBand::AddSymmetric(first + a, first + b, w[a] * w[b], k) for a <= b, entry by entry.
/// @pre 0 <= first and first + 3 < K's n (and D's, with d).
[[gnu::always_inline]] inline void AddOuter(int first, const std::array<double, 4>& w, const Sym3& k, const Sym3* d,
                                            BlockBand* K, BlockBand* D) {
  const Block9 kf = Full(k);
  const Block9 df = d ? Full(*d) : Block9{};
  for (int a = 0; a < 4; ++a) {
    // Row first + a's blocks (first + a, first + b), b >= a, lie side by side.
    double* kb = K->block(first + a, 0).data();
    double* db = d ? D->block(first + a, 0).data() : nullptr;
    for (int b = a; b < 4; ++b) {
      const double wab = w[a] * w[b];
      const V4 s = Splat(wab);
      AddTo({s * kf.lo, s * kf.mid, wab * kf.last}, kb + 9 * (b - a));
      if (d) AddTo({s * df.lo, s * df.mid, wab * df.last}, db + 9 * (b - a));
    }
  }
}

}  // namespace viscera::mechanics::contact_window

