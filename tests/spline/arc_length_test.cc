#include "spline/arc_length.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace viscera::spline {
namespace {

TEST(ArcLengthTable, InvertsArcLengthOnAHelix) {
  const int n = 60;
  Points q(n, 3);
  for (int i = 0; i < n; ++i) {
    const double a = 4.0 * M_PI * i / (n - 1);
    q.row(i) << 0.1 * std::cos(a), 0.1 * std::sin(a), 0.02 * a;
  }
  const CatmullRom curve(n);
  ArcLengthTable table(8);
  table.Build(curve, q);
  EXPECT_NEAR(table.total_length(), curve.Length(q), 1e-6 * curve.Length(q));
  for (double arc = 0.0; arc < table.total_length(); arc += 0.05) {
    const double s = table.ParameterAt(arc);
    EXPECT_NEAR(table.ArcLengthAt(s), arc, 1e-9);
  }
  EXPECT_EQ(table.ParameterAt(-1.0), 0.0);
  EXPECT_EQ(table.ParameterAt(1e9), 1.0);
}

TEST(ArcLengthTable, InvertsArcLengthOnAnUnevenlySpreadCurve) {
  // Control points spread 3 to 1 along a tight coil: the speed varies by half within a segment.
  const int n = 60;
  Points q(n, 3);
  double arc = 0.0;
  for (int i = 0; i < n; ++i) {
    q.row(i) << 0.024 * std::cos(arc / 0.024), 0.024 * std::sin(arc / 0.024), 0.01 * arc;
    arc += 0.016 * (i % 2 == 0 ? 1.5 : 0.5);
  }
  const CatmullRom curve(n);
  ArcLengthTable table(2);
  table.Build(curve, q);
  const double interval = table.total_length() / (2 * (n - 1));
  double worst = 0.0;
  for (int k = 0; k <= 20000; ++k) {
    const double a = table.total_length() * k / 20000;
    const double s = table.ParameterAt(a);
    worst = std::max(worst, std::abs(table.ArcLengthAt(s) - a));
    EXPECT_GE(s, 0.0);
    EXPECT_LE(s, 1.0);
  }
  EXPECT_LT(worst, 5e-4 * interval);
  // A sweep with a hint finds the same parameters as the searches.
  size_t hint = 0;
  for (int k = 0; k <= 2000; ++k) {
    const double a = table.total_length() * k / 2000;
    EXPECT_EQ(table.ParameterAt(a, &hint), table.ParameterAt(a));
  }
}

TEST(ArcLengthTable, UniformOnAStraightLine) {
  const int n = 5;
  Points q(n, 3);
  for (int i = 0; i < n; ++i) q.row(i) << 0.0, 0.0, 0.25 * i;
  const CatmullRom curve(n);
  ArcLengthTable table(4);
  table.Build(curve, q);
  EXPECT_NEAR(table.total_length(), 1.0, 1e-14);
  EXPECT_NEAR(table.ParameterAt(0.3), 0.3, 1e-12);
}

}  // namespace
}  // namespace viscera::spline
