#include "mechanics/block_band_cholesky.h"

#include "mechanics/avx_clone.h"
#include "mechanics/simd_lanes.h"

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace viscera::mechanics {
namespace {

constexpr int kBand = BlockBand::kWidth - 1;  // 3 blocks below the diagonal

// Lower Cholesky factor of a 3x3 SPD block and its inverse; false if not PD.
[[gnu::always_inline]] inline bool Chol3(const Mat3& s, Mat3* inv) {
  const double l00sq = s(0, 0);
  if (!(l00sq > 0.0)) return false;
  const double l00 = std::sqrt(l00sq);
  const double l10 = s(1, 0) / l00, l20 = s(2, 0) / l00;
  const double l11sq = s(1, 1) - l10 * l10;
  if (!(l11sq > 0.0)) return false;
  const double l11 = std::sqrt(l11sq);
  const double l21 = (s(2, 1) - l20 * l10) / l11;
  const double l22sq = s(2, 2) - l20 * l20 - l21 * l21;
  if (!(l22sq > 0.0)) return false;
  const double l22 = std::sqrt(l22sq);
  // Inverse of the lower triangle [l00 0 0; l10 l11 0; l20 l21 l22].
  const double i00 = 1.0 / l00, i11 = 1.0 / l11, i22 = 1.0 / l22;
  const double i10 = -l10 * i00 * i11;
  const double i21 = -l21 * i11 * i22;
  const double i20 = -(l20 * i00 + l21 * i10) * i22;
  *inv << i00, 0.0, 0.0, i10, i11, 0.0, i20, i21, i22;
  return true;
}

// A(i, j) for i >= j from the upper block storage.
Mat3 Lower(const BlockBand& a, int i, int j) { return a.block(j, i - j).transpose(); }

}  // namespace

VISCERA_AVX_CLONE bool BlockBandCholesky::Factor(const BlockBand& a) {
  n_ = a.n();
  l_.resize(static_cast<size_t>(n_) * BlockBand::kWidth);
  inv_diag_.resize(n_);
  for (int j = 0; j < n_; ++j) {
    // Diagonal: S = A(j,j) - sum_k L(j,k) L(j,k)^T, L(j,j) = chol(S).
    Mat3 s = a.block(j, 0);
    for (int d = 1; d <= std::min(j, kBand); ++d) s.noalias() -= L(j, d) * L(j, d).transpose();
    if (!Chol3(s, &inv_diag_[j])) return false;
    // Below: L(i,j) = (A(i,j) - sum_k L(i,k) L(j,k)^T) L(j,j)^-T for k < j within both bands.
    for (int i = j + 1; i <= std::min(n_ - 1, j + kBand); ++i) {
      Mat3 b = Lower(a, i, j);
      for (int k = std::max(0, i - kBand); k < j; ++k)
        b.noalias() -= L(i, i - k) * L(j, j - k).transpose();
      L(i, i - j).noalias() = b * inv_diag_[j].transpose();
    }
  }
  return true;
}

namespace {

// One row's 3x3 products, in the association Eigen's Mat3 * Vec3 gave them (the x and y rows
// as one SSE2 packet, (p0 + p1) + p2; the z row a scalar reduction, p0 + (p1 + p2)), and the
// transposed product (three dot products, (p0 + p1) + p2): the band solve's numbers bit for bit,
// written out so that the solve keeps its last three rows in registers rather than storing
// each row and loading it back for the next (a store-to-load round trip on the solve's
// row-to-row chain). Every product is kept, the triangular blocks' zeros included.
// T is double (one right-hand side) or a pair of doubles, two right-hand sides in the lanes of
// one SSE2 register: each lane then does the one-column arithmetic, with the factor's entries
// loaded once for both.
using Pair = lanes::V2;

template <class T>
struct Row3 {
  T x, y, z;
};

template <class T>
[[gnu::always_inline]] inline T Splat(double v) {
  if constexpr (std::is_same_v<T, double>) {
    return v;
  } else if constexpr (std::is_same_v<T, Pair>) {
    return T{v, v};
  } else {
    return T{v, v, v, v};
  }
}

template <class T>
[[gnu::always_inline]] inline Row3<T> Product(const double* m,
                                              const Row3<T>& v) {  // m column-major
  return {(Splat<T>(m[0]) * v.x + Splat<T>(m[3]) * v.y) + Splat<T>(m[6]) * v.z,
          (Splat<T>(m[1]) * v.x + Splat<T>(m[4]) * v.y) + Splat<T>(m[7]) * v.z,
          Splat<T>(m[2]) * v.x + (Splat<T>(m[5]) * v.y + Splat<T>(m[8]) * v.z)};
}

template <class T>
[[gnu::always_inline]] inline Row3<T> TransposedProduct(const double* m, const Row3<T>& v) {
  return {(Splat<T>(m[0]) * v.x + Splat<T>(m[1]) * v.y) + Splat<T>(m[2]) * v.z,
          (Splat<T>(m[3]) * v.x + Splat<T>(m[4]) * v.y) + Splat<T>(m[5]) * v.z,
          (Splat<T>(m[6]) * v.x + Splat<T>(m[7]) * v.y) + Splat<T>(m[8]) * v.z};
}

template <class T>
[[gnu::always_inline]] inline void Subtract(Row3<T>* v, const Row3<T>& p) {
  v->x -= p.x;
  v->y -= p.y;
  v->z -= p.z;
}

// Row i of one right-hand side.
struct OneColumn {
  double* b;
  Row3<double> Load(int i) const { return {b[3 * i], b[3 * i + 1], b[3 * i + 2]}; }
  void Store(int i, const Row3<double>& v) const {
    b[3 * i] = v.x;
    b[3 * i + 1] = v.y;
    b[3 * i + 2] = v.z;
  }
};

// Row i of two right-hand sides, one per lane.
struct TwoColumns {
  double* a;
  double* b;
  Row3<Pair> Load(int i) const {
    return {Pair{a[3 * i], b[3 * i]}, Pair{a[3 * i + 1], b[3 * i + 1]},
            Pair{a[3 * i + 2], b[3 * i + 2]}};
  }
  void Store(int i, const Row3<Pair>& v) const {
    a[3 * i] = v.x[0];
    b[3 * i] = v.x[1];
    a[3 * i + 1] = v.y[0];
    b[3 * i + 1] = v.y[1];
    a[3 * i + 2] = v.z[0];
    b[3 * i + 2] = v.z[1];
  }
};

// Row i of four right-hand sides, one per lane.
struct FourColumns {
  double* a;
  double* b;
  double* c;
  double* d;
  Row3<lanes::V4> Load(int i) const {
    return {lanes::V4{a[3 * i], b[3 * i], c[3 * i], d[3 * i]},
            lanes::V4{a[3 * i + 1], b[3 * i + 1], c[3 * i + 1], d[3 * i + 1]},
            lanes::V4{a[3 * i + 2], b[3 * i + 2], c[3 * i + 2], d[3 * i + 2]}};
  }
  void Store(int i, const Row3<lanes::V4>& v) const {
    for (int k = 0; k < 3; ++k) {
      const lanes::V4 row = k == 0 ? v.x : k == 1 ? v.y : v.z;
      a[3 * i + k] = row[0];
      b[3 * i + k] = row[1];
      c[3 * i + k] = row[2];
      d[3 * i + k] = row[3];
    }
  }
};

}  // namespace

template <class T, class Rows>
[[gnu::always_inline]] inline void BlockBandCholesky::Solve(const Rows& rows, int first) const {
  // y1, y2, y3: the last three rows of the pass, newest first, in named registers (an array
  // indexed by the band's offset went through memory and gave nothing; this takes a third off
  // the solve).
  Row3<T> y1{}, y2{}, y3{};
  // Forward: L y = b, y_i = L(i,i)^-1 (b_i - sum_d L(i, i - d) y_(i-d)), d = 1, 2, 3 in order.
  // Rows of +0 before `first` give y = +0 (L(i,i)^-1's diagonal is positive, and +0 less a
  // product of +0 is +0): the pass starts at `first` with y1 = y2 = y3 = +0, as it reaches it.
  for (int i = std::clamp(first, 0, n_); i < n_; ++i) {
    Row3<T> v = rows.Load(i);
    if (i >= 1) Subtract(&v, Product(L(i, 1).data(), y1));
    if (i >= 2) Subtract(&v, Product(L(i, 2).data(), y2));
    if (i >= 3) Subtract(&v, Product(L(i, 3).data(), y3));
    const Row3<T> y = Product(inv_diag_[i].data(), v);
    rows.Store(i, y);
    y3 = y2;
    y2 = y1;
    y1 = y;
  }
  // Backward: L^T x = y, x_i = L(i,i)^-T (y_i - sum_d L(i + d, i)^T x_(i+d)).
  for (int i = n_ - 1; i >= 0; --i) {
    Row3<T> v = rows.Load(i);
    if (i + 1 < n_) Subtract(&v, TransposedProduct(L(i + 1, 1).data(), y1));
    if (i + 2 < n_) Subtract(&v, TransposedProduct(L(i + 2, 2).data(), y2));
    if (i + 3 < n_) Subtract(&v, TransposedProduct(L(i + 3, 3).data(), y3));
    const Row3<T> x = TransposedProduct(inv_diag_[i].data(), v);
    rows.Store(i, x);
    y3 = y2;
    y2 = y1;
    y1 = x;
  }
}

VISCERA_AVX_CLONE void BlockBandCholesky::SolveInPlace(double* b, int first) const {
  Solve<double>(OneColumn{b}, first);
}

VISCERA_AVX_CLONE void BlockBandCholesky::SolveTwoInPlace(double* a, double* b, int first) const {
  Solve<Pair>(TwoColumns{a, b}, first);
}

VISCERA_AVX_CLONE void BlockBandCholesky::SolveFourInPlace(double* a, double* b, double* c,
                                                           double* d, int first) const {
  Solve<lanes::V4>(FourColumns{a, b, c, d}, first);
}

}  // namespace viscera::mechanics
