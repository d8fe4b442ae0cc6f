#include "collision/pair_separation.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace viscera::collision {
namespace {

uint64_t Bits(double x) { return std::bit_cast<uint64_t>(x); }

// The contacts' self-pair geometry as ContactGeometry::Raw computed it before the four-lane
// kernel: both forms must give these bits.
PairSeparation AsBefore(const Vec3& a, const Vec3& b) {
  const Vec3 d = a - b;
  const double distance = d.norm();
  return {distance, distance > 1e-12 ? Vec3(d * (1.0 / distance)) : Vec3::UnitZ()};
}

void ExpectSameBits(const PairSeparation& got, const PairSeparation& want, int i) {
  ASSERT_EQ(Bits(got.distance), Bits(want.distance)) << i;
  for (int k = 0; k < 3; ++k) ASSERT_EQ(Bits(got.normal(k)), Bits(want.normal(k))) << i << " " << k;
}

TEST(PairSeparation, FourLanesGiveTheOnePairFormsBitsForEveryCount) {
  // Sphere centres in a 0.4 m cavity, pairs from touching (radius 12.5 mm) to across it, and the
  // edge cases: coincident, within 1e-12 m, non-finite.
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-0.2, 0.2), scale(-14.0, 0.0);
  std::vector<Vec3> a, b;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const Vec3 dir = Vec3(u(rng), u(rng), u(rng)).normalized();
    a.push_back(p);
    b.push_back(i % 2 ? Vec3(p + std::pow(10.0, scale(rng)) * dir) : Vec3(u(rng), u(rng), u(rng)));
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Vec3& d : {Vec3(0, 0, 0), Vec3(3e-13, 0, 4e-13), Vec3(1e-12, 0, 0), Vec3(nan, 0, 0),
                        Vec3(std::numeric_limits<double>::infinity(), 0, 0)}) {
    a.push_back(Vec3(0.1, 0.05, 0.02) + d);
    b.push_back(Vec3(0.1, 0.05, 0.02));
  }
  int compared = 0;
  for (int count = 1; count <= 4; ++count) {
    for (size_t i = 0; i + count <= a.size(); i += count) {
      std::array<const Vec3*, 4> pa{}, pb{};
      for (int l = 0; l < count; ++l) {
        pa[l] = &a[i + l];
        pb[l] = &b[i + l];
      }
      std::array<PairSeparation, 4> out;
      Separations(pa, pb, count, out.data());
      for (int l = 0; l < count; ++l) {
        const PairSeparation want = AsBefore(a[i + l], b[i + l]);
        ExpectSameBits(Separation(a[i + l], b[i + l]), want, static_cast<int>(i) + l);
        ExpectSameBits(out[l], want, static_cast<int>(i) + l);
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 4 * 4000);
  // The edge cases did what the contacts rely on: +z below 1e-12 m, NaN kept in the distance.
  EXPECT_EQ(Separation(a[4000], b[4000]).normal, Vec3::UnitZ());
  EXPECT_EQ(Separation(a[4001], b[4001]).normal, Vec3::UnitZ());
  EXPECT_TRUE(std::isnan(Separation(a[4003], b[4003]).distance));
}

}  // namespace
}  // namespace viscera::collision
