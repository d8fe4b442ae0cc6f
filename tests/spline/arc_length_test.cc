#include "spline/arc_length.h"

#include <gtest/gtest.h>

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
  // A sweep with a hint finds exactly what the searches find, in steps shorter and longer than
  // the table's intervals.
  for (const double step : {0.001, 0.013, 0.07}) {
    size_t hint = 0;
    for (double arc = -0.01; arc < table.total_length() + 0.02; arc += step) {
      EXPECT_EQ(table.ParameterAt(arc, &hint), table.ParameterAt(arc)) << arc;
    }
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
