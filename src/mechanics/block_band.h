#pragma once
/// A symmetric 3N x 3N matrix made of 3x3 blocks (i, j) with |i - j| <= 3: the pattern of every
/// force Jacobian of the Catmull-Rom chain (springs, stretching energy, attachments). Stores
/// the upper blocks: block(i, d) = A(i, i + d).
#include <vector>

#include "common/check.h"
#include "common/types.h"

namespace viscera::mechanics {

class BlockBand {
 public:
  static constexpr int kWidth = 4;  // d = 0..3

  explicit BlockBand(int n = 0) { Resize(n); }
  void Resize(int n) {
    n_ = n;
    blocks_.assign(static_cast<size_t>(n) * kWidth, Mat3::Zero());
  }
  void SetZero() {
    for (Mat3& b : blocks_) b.setZero();
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

  /// y = A x (#N by 3 each).
  void Multiply(const Points& x, Points* y) const {
    y->setZero();
    for (int i = 0; i < n_; ++i) {
      y->row(i) += (block(i, 0) * x.row(i).transpose()).transpose();
      for (int d = 1; d < kWidth && i + d < n_; ++d) {
        y->row(i) += (block(i, d) * x.row(i + d).transpose()).transpose();
        y->row(i + d) += (block(i, d).transpose() * x.row(i).transpose()).transpose();
      }
    }
  }

 private:
  int n_ = 0;
  std::vector<Mat3> blocks_;
};

}  // namespace viscera::mechanics
