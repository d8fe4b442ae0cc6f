#pragma once
/// A contact point's window of 4 control points and its weights (ContactWindow): the one place
/// that gathers a point's motion from its control points and scatters its force and stiffness
/// back. The lane kernels below carry the force onto F's 4 rows and the 3x3 stiffness and damping
/// onto K's and D's 10 window blocks, 4 entries per vector (simd_lanes.h: SSE2 pairs in the
/// baseline code, one AVX register in an AVX clone). Each entry gets the products and sums the
/// scalar code gave it, in its order, so the numbers are the scalar code's bit for bit
/// (tests/mechanics/contact_window_test.cc holds them to it).
#include <array>

#include "collision/sphere_chain.h"
#include "common/types.h"
#include "mechanics/block_band.h"
#include "mechanics/model.h"
#include "mechanics/simd_lanes.h"

namespace viscera::mechanics {
namespace contact_window {

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

}  // namespace contact_window

/// A point of the tube (a contact sphere's centre, a grasped curve point) as the control points
/// see it: J = [w_0 I, w_1 I, w_2 I, w_3 I] on rows first to first + 3. Contacts, grasps, tip
/// links, self pairs and friction pairs all carry one, so that the point's motion is gathered
/// and its force scattered by the same few lines, in the same order everywhere.
struct ContactWindow {
  int first = 0;              ///< first control point
  std::array<double, 4> w{};  ///< b_{first+a}(s)

  static ContactWindow Of(const collision::Sphere& sphere) { return {sphere.first, sphere.w}; }
  static ContactWindow Of(const CurvePoint& p) {
    return {p.first, {p.w(0), p.w(1), p.w(2), p.w(3)}};
  }

  /// J (x + dx): sum over a of w_a (x_{first+a} + dx_{first+a}), in that order (x #N by 3; dx
  /// its 3N values, or nullptr for none).
  Vec3 Gather(const Points& x, const double* dx = nullptr) const {
    Vec3 m = Vec3::Zero();
    for (int a = 0; a < 4; ++a) {
      Vec3 point = x.row(first + a).transpose();
      if (dx != nullptr) point += Eigen::Map<const Vec3>(dx + 3 * (first + a));
      m += w[a] * point;
    }
    return m;
  }
  /// J x, x's 3N values.
  Vec3 Gather(const double* x) const {
    Vec3 m = Vec3::Zero();
    for (int a = 0; a < 4; ++a) m += w[a] * Eigen::Map<const Vec3>(x + 3 * (first + a));
    return m;
  }
  /// F += J^T f (F: #N by 3, or its 3N values).
  void Scatter(const Vec3& f, Points* F) const { Scatter(f, F->data()); }
  void Scatter(const Vec3& f, double* F) const { contact_window::AddForce(F, first, w, f); }
  /// K += J^T k J and D += J^T d J if d is given (k, d symmetric: contact_window::AddOuter).
  void AddOuter(const Mat3& k, const Mat3* d, BlockBand* K, BlockBand* D) const;
};

/// (J_a + J_b) x for two windows on x's 3N values, a's and b's terms of each point summed first
/// (the self pairs' common motion, at every CG product: x and y two at a time, z alone).
[[gnu::always_inline]] inline Vec3 GatherCommon(const ContactWindow& a, const ContactWindow& b,
                                                const double* x) {
  using Pair2 = Eigen::Vector2d;
  using In2 = Eigen::Map<const Pair2>;
  const double* xa = x + 3 * a.first;
  const double* xb = x + 3 * b.first;
  Pair2 xy = Pair2::Zero();
  double z = 0.0;
  for (int i = 0; i < 4; ++i) {
    xy += a.w[i] * In2(xa + 3 * i) + b.w[i] * In2(xb + 3 * i);
    z += a.w[i] * xa[3 * i + 2] + b.w[i] * xb[3 * i + 2];
  }
  return Vec3(xy(0), xy(1), z);
}

}  // namespace viscera::mechanics
