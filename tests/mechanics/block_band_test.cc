#include "mechanics/block_band_cholesky.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

namespace viscera::mechanics {
namespace {

// A random symmetric positive definite block band (diagonally dominant) and its dense copy.
BlockBand RandomSpdBand(int n, unsigned seed, MatX* dense) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  BlockBand a(n);
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < BlockBand::kWidth && i + d < n; ++d) {
      Mat3 m;
      for (int k = 0; k < 9; ++k) m(k / 3, k % 3) = u(rng);
      if (d == 0) m = (m + m.transpose()).eval() + 30.0 * Mat3::Identity();
      a.block(i, d) = m;
    }
  }
  *dense = MatX::Zero(3 * n, 3 * n);
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < BlockBand::kWidth && i + d < n; ++d) {
      dense->block<3, 3>(3 * i, 3 * (i + d)) = a.block(i, d);
      dense->block<3, 3>(3 * (i + d), 3 * i) = a.block(i, d).transpose();
    }
  }
  return a;
}

VecX RandomVector(int size, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  VecX v(size);
  for (double& x : v) x = normal(rng);
  return v;
}

TEST(BlockBand, MultiplyAndSolveMatchTheDenseMatrix) {
  const int n = 40;
  MatX dense;
  const BlockBand a = RandomSpdBand(n, 3, &dense);
  const VecX b = RandomVector(3 * n, 4);

  Points x = Eigen::Map<const Points>(b.data(), n, 3), y(n, 3);
  a.Multiply(x, &y);
  EXPECT_LT((Eigen::Map<const VecX>(y.data(), 3 * n) - dense * b).cwiseAbs().maxCoeff(),
            1e-12 * (dense * b).norm());

  BlockBandCholesky chol;
  ASSERT_TRUE(chol.Factor(a));
  VecX solved = b;
  chol.SolveInPlace(solved.data());
  const VecX expected = dense.ldlt().solve(b);
  EXPECT_LT((solved - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff());
}

// y = A x as the band product was first written: a pass over the upper blocks that scatters
// both halves into y. Multiply sums each row in registers in the same order; the numbers must
// not move.
Points ScatterMultiply(const BlockBand& a, const Points& x) {
  Points y = Points::Zero(a.n(), 3);
  for (int i = 0; i < a.n(); ++i) {
    y.row(i) += (a.block(i, 0) * x.row(i).transpose()).transpose();
    for (int d = 1; d < BlockBand::kWidth && i + d < a.n(); ++d) {
      y.row(i) += (a.block(i, d) * x.row(i + d).transpose()).transpose();
      y.row(i + d) += (a.block(i, d).transpose() * x.row(i).transpose()).transpose();
    }
  }
  return y;
}

TEST(BlockBand, MultiplyIsTheScatterPassBitForBit) {
  for (const int n : {1, 2, 3, 4, 5, 7, 40}) {
    SCOPED_TRACE(n);
    MatX dense;
    const BlockBand a = RandomSpdBand(n, 10 + n, &dense);
    const VecX b = RandomVector(3 * n, 20 + n);
    const Points x = Eigen::Map<const Points>(b.data(), n, 3);
    const Points expected = ScatterMultiply(a, x);
    Points y(n, 3);
    a.Multiply(x, &y);
    EXPECT_EQ(std::memcmp(y.data(), expected.data(), sizeof(double) * 3 * n), 0);
    Points raw = Points::Constant(n, 3, 1e300);  // the pointer form overwrites every entry
    a.Multiply(x.data(), raw.data());
    EXPECT_EQ(std::memcmp(raw.data(), expected.data(), sizeof(double) * 3 * n), 0);
  }
}

// The band solve as first written, with Eigen's 3x3 products on each row read back from memory.
// The solve now keeps its last three rows in registers and writes the products out; its
// numbers must not move (in the first rows, the edges of the band, and inside).
void EigenSolve(const BlockBandCholesky& chol, double* b) {
  using Vec = Eigen::Map<Vec3>;
  const int n = chol.n();
  for (int i = 0; i < n; ++i) {
    Vec3 v = Vec(b + 3 * i);
    for (int d = 1; d <= std::min(i, 3); ++d)
      v.noalias() -= chol.lower_block(i, d) * Vec(b + 3 * (i - d));
    Vec(b + 3 * i).noalias() = chol.inverse_diagonal(i) * v;
  }
  for (int i = n - 1; i >= 0; --i) {
    Vec3 v = Vec(b + 3 * i);
    for (int d = 1; d <= std::min(n - 1 - i, 3); ++d) {
      v.noalias() -= chol.lower_block(i + d, d).transpose() * Vec(b + 3 * (i + d));
    }
    Vec(b + 3 * i).noalias() = chol.inverse_diagonal(i).transpose() * v;
  }
}

// The one-column solve against Eigen's row-by-row solve, and the two- and four-column solves
// (one column per lane) against it, bit for bit.
TEST(BlockBand, SolveIsEigensRowByRowSolveBitForBit) {
#if defined(__AVX__)
  GTEST_SKIP() << "the solve keeps Eigen's SSE2 association; built for AVX (VISCERA_NATIVE=ON), "
                  "Eigen sums otherwise";
#endif
  for (const int n : {1, 2, 3, 4, 5, 7, 40}) {
    SCOPED_TRACE(n);
    MatX dense;
    BlockBandCholesky chol;
    ASSERT_TRUE(chol.Factor(RandomSpdBand(n, 30 + n, &dense)));
    for (unsigned seed = 0; seed < 20; ++seed) {
      const VecX b = RandomVector(3 * n, 100 * n + seed), c = RandomVector(3 * n, 300 * n + seed);
      VecX expected = b, solved = b, expected_c = c, b_two = b, c_two = c;
      EigenSolve(chol, expected.data());
      EigenSolve(chol, expected_c.data());
      chol.SolveInPlace(solved.data());
      chol.SolveTwoInPlace(b_two.data(), c_two.data());
      EXPECT_EQ(std::memcmp(solved.data(), expected.data(), sizeof(double) * 3 * n), 0) << seed;
      EXPECT_EQ(std::memcmp(b_two.data(), expected.data(), sizeof(double) * 3 * n), 0) << seed;
      EXPECT_EQ(std::memcmp(c_two.data(), expected_c.data(), sizeof(double) * 3 * n), 0) << seed;
      // Four: b and c in two lanes each (lanes 0 and 3 are b, 1 and 2 are c).
      VecX four[4] = {b, c, c, b};
      chol.SolveFourInPlace(four[0].data(), four[1].data(), four[2].data(), four[3].data());
      for (int lane = 0; lane < 4; ++lane) {
        const VecX& want = lane == 0 || lane == 3 ? expected : expected_c;
        EXPECT_EQ(std::memcmp(four[lane].data(), want.data(), sizeof(double) * 3 * n), 0)
            << seed << " lane " << lane;
      }
    }
  }
}

// A right-hand side that is +0 before block `first` (the tips' columns): the solve that starts
// its forward pass there gives the whole solve's numbers, bit for bit, one column or two; and
// the forward pass does read the rows it starts at (a wrong start would change the answer).
TEST(BlockBand, SolveFromFirstNonzeroBlockIsTheWholeSolveBitForBit) {
  const int n = 40;
  MatX dense;
  BlockBandCholesky chol;
  ASSERT_TRUE(chol.Factor(RandomSpdBand(n, 77, &dense)));
  for (const int first : {0, 1, 3, 17, 36, 39}) {
    SCOPED_TRACE(first);
    VecX b = RandomVector(3 * n, 500 + first), c = RandomVector(3 * n, 700 + first);
    b.head(3 * first).setZero();
    c.head(3 * first).setZero();
    VecX whole = b, whole_c = c, from = b, two_b = b, two_c = c;
    chol.SolveInPlace(whole.data());
    chol.SolveInPlace(whole_c.data());
    chol.SolveInPlace(from.data(), first);
    chol.SolveTwoInPlace(two_b.data(), two_c.data(), first);
    EXPECT_EQ(std::memcmp(from.data(), whole.data(), sizeof(double) * 3 * n), 0);
    EXPECT_EQ(std::memcmp(two_b.data(), whole.data(), sizeof(double) * 3 * n), 0);
    EXPECT_EQ(std::memcmp(two_c.data(), whole_c.data(), sizeof(double) * 3 * n), 0);
    VecX four_b = b, four_c = c, four_b2 = b, four_c2 = c;
    chol.SolveFourInPlace(four_b.data(), four_c.data(), four_b2.data(), four_c2.data(), first);
    EXPECT_EQ(std::memcmp(four_b.data(), whole.data(), sizeof(double) * 3 * n), 0);
    EXPECT_EQ(std::memcmp(four_c.data(), whole_c.data(), sizeof(double) * 3 * n), 0);
    EXPECT_EQ(std::memcmp(four_b2.data(), whole.data(), sizeof(double) * 3 * n), 0);
    EXPECT_EQ(std::memcmp(four_c2.data(), whole_c.data(), sizeof(double) * 3 * n), 0);
    if (first + 1 < n) {
      VecX late = b;
      chol.SolveInPlace(late.data(), first + 1);  // skips block `first`'s nonzero rows
      EXPECT_GT((late - whole).norm(), 0.0);
    }
  }
}

TEST(BlockBand, FactorRefusesAnIndefiniteMatrix) {
  MatX dense;
  BlockBand a = RandomSpdBand(10, 8, &dense);
  a.block(6, 0)(1, 1) = -100.0;
  BlockBandCholesky chol;
  EXPECT_FALSE(chol.Factor(a));
}

TEST(BlockBand, AddSymmetricIsAddOfTheScaledBlockBitForBit) {
  // Above, below and on the diagonal: the same stored numbers as Add(i, j, s h).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Mat3 h;
  for (int r = 0; r < 3; ++r) {
    for (int c = r; c < 3; ++c) h(r, c) = h(c, r) = u(rng);
  }
  MatX unused;
  BlockBand a = RandomSpdBand(8, 3, &unused);
  BlockBand b = a;
  const double s = -0.37;
  for (const auto& [i, j] : std::vector<std::pair<int, int>>{{2, 5}, {6, 3}, {4, 4}, {0, 1}}) {
    a.Add(i, j, s * h);
    b.AddSymmetric(i, j, s, ToSym3(h));
  }
  for (int i = 0; i < 8; ++i) {
    for (int d = 0; d < BlockBand::kWidth; ++d) {
      for (int k = 0; k < 9; ++k)
        EXPECT_EQ(a.block(i, d)(k / 3, k % 3), b.block(i, d)(k / 3, k % 3)) << i << " " << d;
    }
  }
}

}  // namespace
}  // namespace viscera::mechanics
