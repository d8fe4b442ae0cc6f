#include "spline/catmull_rom.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/check.h"

namespace viscera::spline {
namespace {

Points RandomPoints(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  Points q(n, 3);
  for (int i = 0; i < n; ++i) q.row(i) << uni(rng), uni(rng), uni(rng);
  return q;
}

Points Line(int n, const Vec3& start, const Vec3& step) {
  Points q(n, 3);
  for (int i = 0; i < n; ++i) q.row(i) = (start + i * step).transpose();
  return q;
}

TEST(CatmullRom, RejectsFewerThanFourPoints) { EXPECT_THROW(CatmullRom(3), InputError); }

TEST(CatmullRom, BasisIsPartitionOfUnity) {
  for (int n : {4, 5, 9, 50}) {
    const CatmullRom curve(n);
    for (int j = 0; j < curve.num_segments(); ++j) {
      for (double u = 0.0; u <= 1.0; u += 0.0625) {
        const SegmentBasis b = curve.Basis(j, u);
        EXPECT_NEAR(b.w[0] + b.w[1] + b.w[2] + b.w[3], 1.0, 1e-14) << "n=" << n << " j=" << j;
        EXPECT_NEAR(b.dw[0] + b.dw[1] + b.dw[2] + b.dw[3], 0.0, 1e-13);
        EXPECT_NEAR(b.ddw[0] + b.ddw[1] + b.ddw[2] + b.ddw[3], 0.0, 1e-12);
      }
    }
  }
}

TEST(CatmullRom, InterpolatesControlPointsAndIsContinuous) {
  const int n = 12;
  const CatmullRom curve(n);
  const Points q = RandomPoints(n, 7);
  for (int i = 0; i < n; ++i) {
    const double s = static_cast<double>(i) / (n - 1);
    EXPECT_LT((curve.Position(q, s) - q.row(i).transpose()).norm(), 1e-13) << i;
  }
  // C1 across segment joints: the end of segment j-1 and the start of segment j agree in
  // position and in tangent.
  auto eval = [&](int j, double u, bool derivative) {
    const SegmentBasis b = curve.Basis(j, u);
    Vec3 p = Vec3::Zero();
    for (int a = 0; a < 4; ++a)
      p += (derivative ? b.dw[a] : b.w[a]) * q.row(b.first + a).transpose();
    return p;
  };
  for (int j = 1; j < curve.num_segments(); ++j) {
    EXPECT_LT((eval(j - 1, 1.0, false) - eval(j, 0.0, false)).norm(), 1e-13) << j;
    EXPECT_LT((eval(j - 1, 1.0, true) - eval(j, 0.0, true)).norm(), 1e-12) << j;
  }
}

TEST(CatmullRom, ReproducesStraightLinesWithUniformSpeedAndReflectedEnds) {
  const int n = 10;
  const CatmullRom curve(n);
  const Vec3 step(0.1, -0.2, 0.05);
  const Points q = Line(n, Vec3(1, 2, 3), step);
  for (double s = 0.0; s <= 1.0; s += 0.01) {
    const Vec3 expected = Vec3(1, 2, 3) + s * (n - 1) * step;
    EXPECT_LT((curve.Position(q, s) - expected).norm(), 1e-13);
    EXPECT_LT((curve.Tangent(q, s) - (n - 1) * step).norm(), 1e-12);
    EXPECT_NEAR(curve.Curvature(q, s), 0.0, 1e-10);
  }
  EXPECT_NEAR(curve.Length(q), (n - 1) * step.norm(), 1e-13);
}

TEST(CatmullRom, CurvatureOfSampledCircle) {
  // 200 points on a circle of radius 0.3: curvature close to 1 / 0.3 away from the ends.
  const int n = 200;
  const double r = 0.3;
  Points q(n, 3);
  for (int i = 0; i < n; ++i) {
    const double a = 1.5 * M_PI * i / (n - 1);
    q.row(i) << r * std::cos(a), r * std::sin(a), 0.0;
  }
  const CatmullRom curve(n);
  for (double s = 0.1; s <= 0.9; s += 0.05) EXPECT_NEAR(curve.Curvature(q, s), 1.0 / r, 1e-3 / r);
  EXPECT_NEAR(curve.Length(q), 1.5 * M_PI * r, 1e-5);
}

TEST(CatmullRom, GeneralizedForceSumsToForceAndMatchesBasis) {
  const int n = 8;
  const CatmullRom curve(n);
  const Vec3 f(1.0, -2.0, 0.5);
  for (double s : {0.0, 0.03, 0.5, 0.77, 1.0}) {
    Points Q = Points::Zero(n, 3);
    curve.AddForce(s, f, &Q);
    EXPECT_LT((Q.colwise().sum().transpose() - f).norm(), 1e-14);
    // Virtual work: Q . dq equals F . dP for any displacement dq (P is linear in q).
    const Points dq = RandomPoints(n, 3);
    const Points zero = Points::Zero(n, 3);
    const double work_q = (Q.array() * dq.array()).sum();
    const double work_p = f.dot(curve.Position(dq, s) - curve.Position(zero, s));
    EXPECT_NEAR(work_q, work_p, 1e-13);
  }
}

TEST(CatmullRom, EachControlPointInfluencesAtMostFourSegments) {
  const int n = 20;
  const CatmullRom curve(n);
  for (int j = 0; j < curve.num_segments(); ++j) {
    const int f = curve.FirstIndex(j);
    EXPECT_LE(f, j);
    EXPECT_GE(f + 3, j + 1);
    EXPECT_GE(f, 0);
    EXPECT_LE(f + 3, n - 1);
  }
}

}  // namespace
}  // namespace viscera::spline
