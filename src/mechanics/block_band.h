#pragma once
/// A symmetric 3N x 3N matrix made of 3x3 blocks (i, j) with |i - j| <= 3: the pattern of every
/// force Jacobian of the Catmull-Rom chain (springs, stretching energy, attachments). Stores
/// the upper blocks: block(i, d) = A(i, i + d).
#include <algorithm>
#include <array>
#include <cstring>
#include <vector>

#include "common/check.h"
#include "common/types.h"

namespace viscera::mechanics {

/// A symmetric 3x3 block by its 6 entries: xx, yy, zz, xy, xz, yz.
using Sym3 = std::array<double, 6>;

/// The symmetric part's entries of m (m's own if m is symmetric).
inline Sym3 ToSym3(const Mat3& m) {
  return {m(0, 0),
          m(1, 1),
          m(2, 2),
          0.5 * (m(0, 1) + m(1, 0)),
          0.5 * (m(0, 2) + m(2, 0)),
          0.5 * (m(1, 2) + m(2, 1))};
}

class BlockBand {
 public:
  static constexpr int kWidth = 4;  // d = 0..3

  explicit BlockBand(int n = 0) { Resize(n); }
  void Resize(int n) {
    n_ = n;
    blocks_.assign(static_cast<size_t>(n) * kWidth, Mat3::Zero());
  }
  /// Every entry +0.0 (all bits zero), by one memset: the blocks are contiguous doubles.
  void SetZero() {
    if (!blocks_.empty())
      std::memset(Entries(), 0, sizeof(double) * 9 * blocks_.size());  // null when empty
  }
  /// *this = other; by one memcpy when the sizes agree (no allocation).
  void Assign(const BlockBand& other) {
    if (other.n_ != n_) {
      *this = other;
      return;
    }
    if (!blocks_.empty())
      std::memcpy(Entries(), other.blocks_.data()->data(), sizeof(double) * 9 * blocks_.size());
  }
  int n() const { return n_; }

  Mat3& block(int i, int d) { return blocks_[static_cast<size_t>(i) * kWidth + d]; }
  const Mat3& block(int i, int d) const { return blocks_[static_cast<size_t>(i) * kWidth + d]; }

  /// A(i, j) += h, and so A(j, i) += h^T.
  /// @pre |i - j| <= 3.
  void Add(int i, int j, const Mat3& h) {
    VISCERA_ASSERT(std::abs(i - j) < kWidth);
    if (i <= j) {
      block(i, j - i) += h;
    } else {
      block(j, i - j) += h.transpose();
    }
  }

  /// A(i, j) += s h, and so A(j, i) += s h, for a symmetric h: Add(i, j, s h) with 6
  /// multiplications instead of 9, and no transpose.
  /// @pre |i - j| <= 3.
  void AddSymmetric(int i, int j, double s, const Sym3& h) {
    VISCERA_ASSERT(std::abs(i - j) < kWidth);
    double* b = (i <= j ? block(i, j - i) : block(j, i - j)).data();  // column-major 3x3
    const double xx = s * h[0], yy = s * h[1], zz = s * h[2], xy = s * h[3], xz = s * h[4],
                 yz = s * h[5];
    b[0] += xx;
    b[1] += xy;
    b[2] += xz;
    b[3] += xy;
    b[4] += yy;
    b[5] += yz;
    b[6] += xz;
    b[7] += yz;
    b[8] += zz;
  }

  /// y = A x (#N by 3 each; y is sized here).
  /// @pre y is not x.
  void Multiply(const Points& x, Points* y) const {
    VISCERA_ASSERT(x.rows() == n_ && y != &x);
    y->resize(n_, 3);
    Multiply(x.data(), y->data());
  }
  /// The same on 3N values each, ordered x0 y0 z0 x1 ... (a #N by 3 row-major Points' storage).
  /// @pre x_data and y_data each hold 3N values, and do not overlap (y is written row by row
  /// while later rows still read x).
  void Multiply(const double* x_data, double* y_data) const;

 private:
  static_assert(sizeof(Mat3) == 9 * sizeof(double), "a block is 9 contiguous doubles");
  double* Entries() { return blocks_.data()->data(); }  // @pre not empty

  int n_ = 0;
  std::vector<Mat3> blocks_;
};

}  // namespace viscera::mechanics
