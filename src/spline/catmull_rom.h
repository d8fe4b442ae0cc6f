#pragma once
/// Uniform cubic Catmull-Rom segmented spline over control points q_0..q_{N-1}
/// (France et al. 2005, eq. 2): P(s) = sum_k b_k(s) q_k, s in [0, 1] along the whole curve.
///
/// Segment j (0 <= j < N-1) runs from q_j to q_{j+1} over s in [j/(N-1), (j+1)/(N-1)], with
/// local parameter u in [0, 1]. It is weighted by q_{j-1}..q_{j+2}; at the two ends the missing
/// neighbour is a *reflected* phantom point (q_{-1} = 2 q_0 - q_1, q_N = 2 q_{N-1} - q_{N-2}),
/// folded into the real points' weights. Reflection keeps the end tangent at q_1 - q_0 (a
/// duplicated phantom would halve it), reproduces straight lines exactly, and keeps the basis
/// a partition of unity. Every segment therefore reads a window of 4 consecutive control
/// points starting at FirstIndex(j), and b_k has support on at most 4 segments.
#include <array>

#include "common/types.h"

namespace viscera::spline {

/// The 4 basis weights of a segment's window at one local parameter u, and their first and
/// second derivatives with respect to u.
struct SegmentBasis {
  int first = 0;                ///< index of the window's first control point
  std::array<double, 4> w{};    ///< b_{first+a}(u)
  std::array<double, 4> dw{};   ///< d b / du
  std::array<double, 4> ddw{};  ///< d^2 b / du^2
};

class CatmullRom {
 public:
  /// @pre num_points >= 4.
  /// @throws InputError otherwise.
  explicit CatmullRom(int num_points);

  int num_points() const { return num_points_; }
  int num_segments() const { return num_points_ - 1; }

  /// First control point of segment j's window: clamp(j - 1, 0, N - 4).
  int FirstIndex(int segment) const;

  /// Maps a curve parameter s in [0, 1] (clamped) to (segment, u in [0, 1]).
  void Locate(double s, int* segment, double* u) const;

  /// Polynomial coefficients of segment j's window: row a is the weight of control point
  /// FirstIndex(j) + a, column p the coefficient of u^p.
  const Eigen::Matrix4d& Coefficients(int segment) const;

  /// Weights and derivatives (with respect to u) at local parameter u of a segment.
  SegmentBasis Basis(int segment, double u) const;

  /// Same at curve parameter s.
  SegmentBasis BasisAt(double s) const;

  /// P(s), #q = N by 3.
  Vec3 Position(const Points& q, double s) const;
  /// dP/ds (m per unit of the whole-curve parameter).
  Vec3 Tangent(const Points& q, double s) const;
  /// d^2P/ds^2.
  Vec3 SecondDerivative(const Points& q, double s) const;
  /// Curvature |P' x P''| / |P'|^3 (1/m); 0 where the tangent vanishes.
  double Curvature(const Points& q, double s) const;

  /// Generalized force of a force F applied at curve parameter s: Q_i += b_i(s) F.
  /// @pre Q has N rows.
  void AddForce(double s, const Vec3& force, Points* Q) const;

  /// Curve length: each segment's |dP/du| integrated with 4-point Gauss-Legendre.
  double Length(const Points& q) const;

  /// Length of one segment (same quadrature as Length()).
  double SegmentLength(const Points& q, int segment) const;

 private:
  int num_points_;
  Eigen::Matrix4d first_, interior_, last_;
};

}  // namespace viscera::spline
