#include "mechanics/mass_matrix.h"

#include <gtest/gtest.h>

#include <random>

#include "common/check.h"
#include "mechanics/cholmod_solver.h"
#include "spline/gauss_legendre.h"

namespace viscera::mechanics {
namespace {

MatX Dense(const Band& band) {
  const int n = static_cast<int>(band.rows());
  MatX m = MatX::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d <= kHalfBand && i + d < n; ++d) m(i, i + d) = m(i + d, i) = band(i, d);
  }
  return m;
}

// M_ij = m * integral b_i b_j ds by brute-force midpoint quadrature, without the Gram blocks.
MatX BruteForceMass(const spline::CatmullRom& curve, double mass, int samples) {
  const int n = curve.num_points();
  MatX m = MatX::Zero(n, n);
  for (int k = 0; k < samples; ++k) {
    const double s = (k + 0.5) / samples;
    VecX b = VecX::Zero(n);
    const spline::SegmentBasis basis = curve.BasisAt(s);
    for (int a = 0; a < 4; ++a) b(basis.first + a) += basis.w[a];
    m += (mass / samples) * b * b.transpose();
  }
  return m;
}

TEST(MassMatrix, SymmetricBandedPositiveDefiniteAndSumsToTotalMass) {
  for (int n : {4, 5, 7, 30, 250}) {
    const spline::CatmullRom curve(n);
    const double mass = 1.3;
    const MatX m = Dense(BuildMassBand(curve, mass));
    EXPECT_NEAR(m.sum(), mass, 1e-12 * mass) << n;
    EXPECT_TRUE(m.isApprox(m.transpose(), 0.0));
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        if (std::abs(i - j) > 3) {
          EXPECT_EQ(m(i, j), 0.0);
        }
      }
    }
    Eigen::SelfAdjointEigenSolver<MatX> eig(m);
    EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0) << n;
  }
}

TEST(MassMatrix, GaussLegendreIsExact) {
  const spline::CatmullRom curve(9);
  const MatX exact = Dense(BuildMassBand(curve, 2.0));
  const MatX brute = BruteForceMass(curve, 2.0, 200000);
  EXPECT_LT((exact - brute).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(MassMatrix, BandedAndCholmodSolvesMatchDenseSolve) {
  const int n = 60;
  const spline::CatmullRom curve(n);
  const Band band = BuildMassBand(curve, 0.8);
  const MatX dense = Dense(band);
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  Points b(n, 3);
  for (int i = 0; i < n; ++i) b.row(i) << normal(rng), normal(rng), normal(rng);
  const MatX expected = dense.ldlt().solve(MatX(b));

  BandedCholesky banded;
  banded.Factor(band);
  Points x = b;
  banded.SolveInPlace(&x);
  EXPECT_LT((MatX(x) - expected).cwiseAbs().maxCoeff(), 1e-10 * expected.cwiseAbs().maxCoeff());

  CholmodBandSolver cholmod;
  cholmod.Factor(band);
  Points y = b;
  cholmod.SolveInPlace(&y);
  EXPECT_LT((MatX(y) - expected).cwiseAbs().maxCoeff(), 1e-10 * expected.cwiseAbs().maxCoeff());

  Points my(n, 3);
  BandMultiply(band, x, &my);
  EXPECT_LT((my - b).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(MassMatrix, BandedCholeskyRejectsIndefiniteMatrix) {
  Band band = Band::Zero(5, 4);
  band.col(0).setConstant(1.0);
  band(2, 0) = -1.0;
  BandedCholesky chol;
  EXPECT_THROW(chol.Factor(band), InputError);
}

}  // namespace
}  // namespace viscera::mechanics
