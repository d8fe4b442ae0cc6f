#include "skin/segment_kernel.h"

#include <cmath>

#include <gtest/gtest.h>

namespace viscera::skin {
namespace {

// The closed form (sin a1 - sin a2) / d^2 equals the integral of 1 / |p - x|^3 over the
// segment (composite Simpson, 20000 intervals) to 1e-9 relative, for points beside, beyond
// and behind the segment; StraightIsoValue is the same integral at distance R.
TEST(SegmentKernelTest, ClosedFormMatchesQuadrature) {
  KernelSegment seg;
  seg.start = Vec3(0.1, -0.2, 0.3);
  seg.direction = Vec3(1.0, 2.0, -0.5).normalized();
  seg.length = 0.7;
  auto quadrature = [&](const Vec3& p) {
    const int n = 20000;
    double sum = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double l = seg.length * i / n;
      const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      sum += w / std::pow((p - seg.start - l * seg.direction).norm(), 3);
    }
    return sum * seg.length / n / 3.0;
  };
  for (const Vec3& p :
       {Vec3(0.3, 0.4, 0.2), Vec3(1.0, 1.5, 0.0), Vec3(-0.4, -0.9, 0.6), Vec3(0.2, -0.1, 0.9)}) {
    const double exact = quadrature(p);
    EXPECT_NEAR(SegmentField(seg, p, 0.0), exact, 1e-9 * exact);
  }
  const double r = 0.0125;
  KernelSegment line;
  line.start = Vec3(-0.01, 0.0, 0.0);
  line.direction = Vec3::UnitX();
  line.length = 0.025;
  EXPECT_NEAR(StraightIsoValue(r, -0.01, 0.015), SegmentField(line, Vec3(0.0, r, 0.0), 0.0),
              1e-12 / (r * r));
}

}  // namespace
}  // namespace viscera::skin
