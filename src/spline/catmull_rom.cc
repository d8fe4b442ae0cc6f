#include "spline/catmull_rom.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"
#include "spline/gauss_legendre.h"

namespace viscera::spline {
namespace {

// Catmull-Rom (tension 1/2) weights of p0..p3 as cubics in u: row = point, column = power.
Eigen::Matrix4d InteriorCoefficients() {
  Eigen::Matrix4d c;
  c << 0.0, -0.5, 1.0, -0.5,  //
      1.0, 0.0, -2.5, 1.5,    //
      0.0, 0.5, 2.0, -1.5,    //
      0.0, 0.0, -0.5, 0.5;
  return c;
}

}  // namespace

CatmullRom::CatmullRom(int num_points) : num_points_(num_points) {
  ThrowUnless(num_points >= 4, "a Catmull-Rom chain needs at least 4 control points, got ",
              num_points);
  const Eigen::Matrix4d c = InteriorCoefficients();
  // First segment: window q0..q3 holds p1..p3, phantom p0 = 2 q0 - q1.
  first_.setZero();
  first_.row(0) = c.row(1) + 2.0 * c.row(0);
  first_.row(1) = c.row(2) - c.row(0);
  first_.row(2) = c.row(3);
  interior_ = c;
  // Last segment: window q_{N-4}..q_{N-1} holds p0..p2 in its last three slots,
  // phantom p3 = 2 q_{N-1} - q_{N-2}.
  last_.setZero();
  last_.row(1) = c.row(0);
  last_.row(2) = c.row(1) - c.row(3);
  last_.row(3) = c.row(2) + 2.0 * c.row(3);
}

int CatmullRom::FirstIndex(int segment) const {
  return std::clamp(segment - 1, 0, num_points_ - 4);
}

const Eigen::Matrix4d& CatmullRom::Coefficients(int segment) const {
  if (segment == 0) return first_;
  if (segment == num_segments() - 1) return last_;
  return interior_;
}

void CatmullRom::Locate(double s, int* segment, double* u) const {
  const int n = num_segments();
  const double x = std::clamp(s, 0.0, 1.0) * n;
  const int j = std::min(static_cast<int>(x), n - 1);
  *segment = j;
  *u = x - j;
}

SegmentBasis CatmullRom::Basis(int segment, double u) const {
  const Eigen::Matrix4d& c = Coefficients(segment);
  SegmentBasis b;
  b.first = FirstIndex(segment);
  const double u2 = u * u;
  for (int a = 0; a < 4; ++a) {
    b.w[a] = c(a, 0) + c(a, 1) * u + c(a, 2) * u2 + c(a, 3) * u2 * u;
    b.dw[a] = c(a, 1) + 2.0 * c(a, 2) * u + 3.0 * c(a, 3) * u2;
    b.ddw[a] = 2.0 * c(a, 2) + 6.0 * c(a, 3) * u;
  }
  return b;
}

SegmentBasis CatmullRom::BasisAt(double s) const {
  int j;
  double u;
  Locate(s, &j, &u);
  return Basis(j, u);
}

Vec3 CatmullRom::Position(const Points& q, double s) const {
  const SegmentBasis b = BasisAt(s);
  Vec3 p = Vec3::Zero();
  for (int a = 0; a < 4; ++a) p += b.w[a] * q.row(b.first + a).transpose();
  return p;
}

Vec3 CatmullRom::Tangent(const Points& q, double s) const {
  const SegmentBasis b = BasisAt(s);
  Vec3 d = Vec3::Zero();
  for (int a = 0; a < 4; ++a) d += b.dw[a] * q.row(b.first + a).transpose();
  return d * num_segments();  // du/ds = N - 1
}

Vec3 CatmullRom::SecondDerivative(const Points& q, double s) const {
  const SegmentBasis b = BasisAt(s);
  Vec3 d = Vec3::Zero();
  for (int a = 0; a < 4; ++a) d += b.ddw[a] * q.row(b.first + a).transpose();
  const double n = num_segments();
  return d * (n * n);
}

double CatmullRom::Curvature(const Points& q, double s) const {
  const Vec3 d1 = Tangent(q, s);
  const Vec3 d2 = SecondDerivative(q, s);
  const double speed = d1.norm();
  if (speed <= 0.0) return 0.0;
  return d1.cross(d2).norm() / (speed * speed * speed);
}

void CatmullRom::AddForce(double s, const Vec3& force, Points* Q) const {
  const SegmentBasis b = BasisAt(s);
  for (int a = 0; a < 4; ++a) Q->row(b.first + a) += b.w[a] * force.transpose();
}

double CatmullRom::SegmentLength(const Points& q, int segment) const {
  using Rule = GaussLegendre<4>;
  const Eigen::Matrix4d& c = Coefficients(segment);
  const int f = FirstIndex(segment);
  // Polynomial coefficients of P_j(u) (4 by 3): row p is the u^p coefficient.
  const Eigen::Matrix<double, 4, 3> poly = c.transpose() * q.middleRows<4>(f);
  double length = 0.0;
  for (int g = 0; g < 4; ++g) {
    const double u = Rule::kNodes[g];
    const Eigen::RowVector3d d = poly.row(1) + 2.0 * u * poly.row(2) + 3.0 * u * u * poly.row(3);
    length += Rule::kWeights[g] * d.norm();
  }
  return length;
}

double CatmullRom::Length(const Points& q) const {
  double length = 0.0;
  for (int j = 0; j < num_segments(); ++j) length += SegmentLength(q, j);
  return length;
}

}  // namespace viscera::spline
