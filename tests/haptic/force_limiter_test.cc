#include "haptic/force_limiter.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/check.h"

namespace viscera::haptic {
namespace {

TEST(ForceLimiter, CapsTheMagnitudeKeepingTheDirection) {
  ForceLimiter limiter(3.0, 1e9);
  const Vec3 f = limiter.Apply(Vec3(3, 0, 4), 1e-3);
  EXPECT_NEAR(f.norm(), 3.0, 1e-12);
  EXPECT_NEAR(f.x() / f.z(), 0.75, 1e-12);
  EXPECT_EQ(limiter.clamped(), 1);
}

TEST(ForceLimiter, CapsTheRateOfChangePerPeriod) {
  ForceLimiter limiter(10.0, 200.0);  // 0.2 N per 1 ms period
  Vec3 prev = Vec3::Zero();
  for (int i = 1; i <= 30; ++i) {
    const Vec3 f = limiter.Apply(Vec3(0, 0, 5.1), 1e-3);
    EXPECT_LE((f - prev).norm(), 0.2 + 1e-12);
    EXPECT_NEAR(f.z(), std::min(5.1, 0.2 * i), 1e-9);
    prev = f;
  }
  EXPECT_EQ(limiter.rate_limited(), 25);
}

TEST(ForceLimiter, ANonFiniteForceIsCountedAndRampsToZeroWithoutAJump) {
  ForceLimiter limiter(10.0, 500.0);
  for (int i = 0; i < 20; ++i) limiter.Apply(Vec3(0, 2.0, 0), 1e-3);
  ASSERT_NEAR(limiter.last().y(), 2.0, 1e-12);
  for (const double bad : {std::nan(""), double{INFINITY}}) {
    const Vec3 f = limiter.Apply(Vec3(0, bad, 0), 1e-3);
    EXPECT_TRUE(f.allFinite());
  }
  EXPECT_EQ(limiter.nonfinite(), 2);
  EXPECT_NEAR(limiter.last().y(), 1.0, 1e-12);  // two periods of 0.5 N down
  for (int i = 0; i < 2; ++i) limiter.Apply(Vec3(NAN, 0, 0), 1e-3);
  EXPECT_EQ(limiter.last(), Vec3::Zero());
}

TEST(ForceLimiter, RejectsNonPositiveLimits) {
  EXPECT_THROW(ForceLimiter(0.0, 1.0), InputError);
  EXPECT_THROW(ForceLimiter(1.0, 0.0), InputError);
}

}  // namespace
}  // namespace viscera::haptic
