#include "mechanics/contact_impulses.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

namespace viscera::mechanics {
namespace {

// The plain projected Gauss-Seidel, one pass over every speed per change, in the order the
// solver used before it deferred changes four at a time: the numbers SolveContactImpulses must
// reproduce bit for bit (its deferral, its AVX clone and its grouping of sums are speed only).
int ReferenceImpulses(const MatX& g, Eigen::Index count, const VecX& target, double immobile,
                      VecX* lambda, VecX* speed) {
  VecX& l = *lambda;
  VecX& s = *speed;
  l.head(count).setZero();
  for (int sweep = 0; sweep < kMaxContactSweeps; ++sweep) {
    double worst = 0.0;
    for (Eigen::Index i = 0; i < count; ++i) {
      const double gii = g(i, i);
      if (!(gii > immobile)) continue;
      const double next = std::max(0.0, l(i) + (target(i) - s(i)) / gii);
      const double change = next - l(i);
      if (change == 0.0) continue;
      l(i) = next;
      for (Eigen::Index j = 0; j < count; ++j) s(j) += change * g(j, i);
      worst = std::max(worst, std::abs(change) * gii);
    }
    if (worst < 1e-6) return sweep + 1;
  }
  return kMaxContactSweeps;
}

struct Problem {
  MatX delassus;  // stride (rows) larger than count: only the leading count x count block is G
  VecX target, speed;
};

// G = J J^T for a random J (contacts sharing degrees of freedom, so they push on each other),
// approaching speeds, targets ≤ 0; contact `pinned` (if ≥ 0) has no degrees of freedom: G_ii = 0.
Problem RandomProblem(Eigen::Index count, Eigen::Index padding, int pinned, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Index dofs = 2 * count + 1;
  MatX j(count, dofs);
  for (Eigen::Index r = 0; r < count; ++r) {
    for (Eigen::Index c = 0; c < dofs; ++c) j(r, c) = u(rng);
  }
  if (pinned >= 0) j.row(pinned).setZero();
  Problem p;
  p.delassus =
      MatX::Constant(count + padding, count + padding, 1e300);  // the padding must not be read
  p.delassus.topLeftCorner(count, count) = j * j.transpose();
  p.target.resize(count);
  p.speed.resize(count);
  for (Eigen::Index i = 0; i < count; ++i) {
    p.speed(i) = u(rng) - 0.4;              // most approach
    p.target(i) = -0.1 * std::abs(u(rng));  // some may keep a little approach
  }
  return p;
}

bool SameBits(const VecX& a, const VecX& b, Eigen::Index count) {
  return std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<size_t>(count)) == 0;
}

TEST(ContactImpulses, DeferredChangesGiveThePlainGaussSeidelBitForBit) {
  int solved_with_impulses = 0;
  for (Eigen::Index count = 1; count <= 13; ++count) {
    for (unsigned seed = 0; seed < 8; ++seed) {
      for (const Eigen::Index padding : {Eigen::Index{0}, Eigen::Index{3}}) {
        const int pinned = seed % 2 == 1 ? static_cast<int>(seed % count) : -1;
        SCOPED_TRACE(testing::Message() << "count " << count << " seed " << seed << " padding "
                                        << padding << " pinned " << pinned);
        const Problem p =
            RandomProblem(count, padding, pinned, 1000 * static_cast<unsigned>(count) + seed);
        VecX lambda(count), speed = p.speed;
        VecX ref_lambda(count), ref_speed = p.speed;
        const int sweeps =
            SolveContactImpulses(p.delassus, count, p.target, 1e-12, &lambda, &speed);
        const int ref_sweeps =
            ReferenceImpulses(p.delassus, count, p.target, 1e-12, &ref_lambda, &ref_speed);
        EXPECT_EQ(sweeps, ref_sweeps);
        EXPECT_TRUE(SameBits(lambda, ref_lambda, count));
        EXPECT_TRUE(SameBits(speed, ref_speed, count));
        if (pinned >= 0) {
          EXPECT_EQ(lambda(pinned), 0.0);
        }
        if (lambda.maxCoeff() > 0.0 && sweeps > 1) ++solved_with_impulses;
      }
    }
  }
  // The comparison is only worth something where several changes were made across sweeps.
  EXPECT_GT(solved_with_impulses, 100);
}

TEST(ContactImpulses, TheImpulsesMeetTheTargetsWithoutPulling) {
  const Problem p = RandomProblem(13, 2, 5, 7);
  VecX lambda(13), speed = p.speed;
  const int sweeps = SolveContactImpulses(p.delassus, 13, p.target, 1e-12, &lambda, &speed);
  ASSERT_LT(sweeps, kMaxContactSweeps);
  const MatX g = p.delassus.topLeftCorner(13, 13);
  EXPECT_LT((speed - (p.speed + g * lambda)).cwiseAbs().maxCoeff(), 1e-12);
  for (Eigen::Index i = 0; i < 13; ++i) {
    if (i == 5) continue;  // pinned: left alone
    EXPECT_GE(lambda(i), 0.0);
    EXPECT_GE(speed(i), p.target(i) - 1e-5);
    if (lambda(i) > 0.0) {
      EXPECT_NEAR(speed(i), p.target(i), 1e-5);  // no more than the target asks
    }
  }
}

}  // namespace
}  // namespace viscera::mechanics
