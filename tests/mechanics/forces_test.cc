#include "mechanics/forces.h"

#include <gtest/gtest.h>

#include <functional>

#include "test_models.h"

namespace viscera::mechanics {
namespace {

using testing::Perturbed;
using testing::StraightChain;

struct Evaluation {
  Points force;
  Energies energies;
  ForceJacobians jac;
};

Evaluation Evaluate(const Model& model, const Points& q, const Points& qd) {
  StretchScratch scratch;
  scratch.Resize(model.num_points());
  Evaluation e;
  e.force.resize(model.num_points(), 3);
  e.jac.Resize(model.num_points());
  ComputeForces(model, q, qd, {}, &scratch, &e.force, &e.energies, &e.jac);
  return e;
}

MatX DenseStiffness(const ForceJacobians& jac, bool damping) {
  const BlockBand& b = damping ? jac.damping : jac.stiffness;
  const int n = b.n();
  MatX k = MatX::Zero(3 * n, 3 * n);
  for (int i = 0; i < n; ++i) {
    for (int d = 0; d < BlockBand::kWidth && i + d < n; ++d) {
      k.block<3, 3>(3 * i, 3 * (i + d)) += b.block(i, d);
      if (d > 0) k.block<3, 3>(3 * (i + d), 3 * i) += b.block(i, d).transpose();
    }
  }
  if (!damping && jac.rank1_coeff > 0.0) {
    const Eigen::Map<const VecX> u(jac.rank1_u.data(), 3 * n);
    k += jac.rank1_coeff * u * u.transpose();
  }
  return k;
}

// Central differences of the potential energy against the analytic forces F = -dE/dq, and of
// the forces against K = -dF/dq. Tolerances are relative to the largest entry. K is exact only
// where no spring or segment is compressed (under compression its geometric part is clamped to
// keep K positive semi-definite), so the configurations below are stretched.
void CheckGradientsAndHessian(const ModelParams& params, double perturbation, unsigned seed) {
  const Model model(params);
  const Points q = Perturbed(params.initial_q, perturbation, seed);
  const Points qd = Points::Zero(q.rows(), 3);
  const Evaluation at = Evaluate(model, q, qd);
  const double eps = 1e-6;
  Points fd_force(q.rows(), 3);
  MatX fd_k(3 * q.rows(), 3 * q.rows());
  for (int i = 0; i < q.rows(); ++i) {
    for (int a = 0; a < 3; ++a) {
      Points plus = q, minus = q;
      plus(i, a) += eps;
      minus(i, a) -= eps;
      const Evaluation ep = Evaluate(model, plus, qd);
      const Evaluation em = Evaluate(model, minus, qd);
      fd_force(i, a) = -(ep.energies.potential() - em.energies.potential()) / (2 * eps);
      const Points dforce = (ep.force - em.force) / (2 * eps);
      fd_k.col(3 * i + a) = -Eigen::Map<const VecX>(dforce.data(), 3 * q.rows());
    }
  }
  const Points analytic = at.force;
  const double scale = std::max(1.0, analytic.cwiseAbs().maxCoeff());
  EXPECT_LT((analytic - fd_force).cwiseAbs().maxCoeff(), 1e-6 * scale);
  const MatX k = DenseStiffness(at.jac, false);
  const double kscale = std::max(1.0, k.cwiseAbs().maxCoeff());
  Eigen::Index row, col;
  const double err = (k - fd_k).cwiseAbs().maxCoeff(&row, &col);
  EXPECT_LT(err, 1e-5 * kscale) << "at (" << row << ", " << col << "): analytic " << k(row, col)
                                << " vs " << fd_k(row, col);
}

TEST(Forces, GravityGivesFreeFallAtExactlyG) {
  ModelParams p = StraightChain(12);
  p.gravity = Vec3(0.0, 0.0, -9.81);
  const Model model(p);
  const Evaluation e = Evaluate(model, p.initial_q, Points::Zero(12, 3));
  Points a = e.force;
  model.mass_factor().SolveInPlace(&a);
  for (int i = 0; i < 12; ++i) EXPECT_LT((a.row(i).transpose() - p.gravity).norm(), 1e-12);
  // Potential energy is m g h relative to z = 0.
  Points lifted = p.initial_q;
  lifted.col(2).array() += 2.0;
  EXPECT_NEAR(Evaluate(model, lifted, Points::Zero(12, 3)).energies.gravity, p.mass * 9.81 * 2.0,
              1e-12);
}

TEST(Forces, StretchSpringGradientAndHessian) {
  ModelParams p = StraightChain(9, 1.0, 1.1);
  p.stretch_stiffness = 50.0;
  CheckGradientsAndHessian(p, 0.01, 1);
}

TEST(Forces, BendSpringGradientAndHessian) {
  ModelParams p = StraightChain(9, 1.0, 1.1);
  p.bend_stiffness = 1e-3;
  CheckGradientsAndHessian(p, 0.01, 2);
}

TEST(Forces, GlobalContinuousStretchGradientAndHessian) {
  ModelParams p = StraightChain(8, 1.0, 1.15);
  p.continuous_stretch = 3.0;
  p.continuous_scope = ContinuousScope::kGlobal;
  CheckGradientsAndHessian(p, 0.02, 3);
}

TEST(Forces, SegmentContinuousStretchGradientAndHessian) {
  ModelParams p = StraightChain(8, 1.0, 1.15);
  p.continuous_stretch = 3.0;
  p.continuous_scope = ContinuousScope::kSegment;
  CheckGradientsAndHessian(p, 0.005, 4);  // small enough that no segment is compressed
}

TEST(Forces, AttachmentGradientAndHessian) {
  ModelParams p = StraightChain(7);
  p.attachments.push_back({0.0, Vec3(-0.1, 0.05, 0.0), 20.0, 0.0, 0.0});
  p.attachments.push_back({0.37, Vec3(0.3, 0.4, -0.2), 15.0, 0.0, 0.1});
  p.attachments.push_back({1.0, std::nullopt, 10.0, 0.0, 0.0});
  CheckGradientsAndHessian(p, 0.03, 5);
}

TEST(Forces, AllTermsTogetherWithGravity) {
  ModelParams p = StraightChain(10, 1.0, 1.1);
  p.gravity = Vec3(0.0, 0.0, -9.81);
  p.stretch_stiffness = 80.0;
  p.bend_stiffness = 2e-4;
  p.continuous_stretch = 1.0;
  p.attachments.push_back({0.5, Vec3(0.5, 0.0, 0.3), 30.0, 0.0, 0.05});
  CheckGradientsAndHessian(p, 0.003, 6);
}

TEST(Forces, DampingJacobianMatchesFiniteDifferences) {
  ModelParams p = StraightChain(8, 1.0, 1.05);
  p.stretch_stiffness = 10.0;
  p.bend_stiffness = 1e-4;
  p.damping = 0.7;
  p.spring_damping = 3.0;
  p.attachments.push_back({0.25, std::nullopt, 5.0, 0.4, 0.0});
  const Model model(p);
  const Points q = Perturbed(p.initial_q, 0.01, 7);
  const Points qd = Perturbed(Points::Zero(8, 3), 0.5, 8);
  const MatX d = DenseStiffness(Evaluate(model, q, qd).jac, true);
  const double eps = 1e-6;
  for (int i = 0; i < 8; ++i) {
    for (int a = 0; a < 3; ++a) {
      Points plus = qd, minus = qd;
      plus(i, a) += eps;
      minus(i, a) -= eps;
      const Points df =
          (Evaluate(model, q, plus).force - Evaluate(model, q, minus).force) / (2 * eps);
      const VecX column = -Eigen::Map<const VecX>(df.data(), 24);
      EXPECT_LT((d.col(3 * i + a) - column).cwiseAbs().maxCoeff(), 1e-6) << i << "," << a;
    }
  }
}

TEST(Forces, StretchScopesAgreeOnUniformStretch) {
  ModelParams p = StraightChain(11, 1.0, 1.2);
  p.continuous_stretch = 2.0;
  const Model global(p);
  p.continuous_scope = ContinuousScope::kSegment;
  const Model segment(p);
  const Points zero = Points::Zero(11, 3);
  const double eg = Evaluate(global, p.initial_q, zero).energies.continuous;
  const double es = Evaluate(segment, p.initial_q, zero).energies.continuous;
  EXPECT_NEAR(eg, 0.5 * 2.0 * std::pow(1.2 * 1.2 - 1.0, 2), 1e-12);
  EXPECT_NEAR(es, eg, 1e-12);
}

TEST(Forces, BendSpringsMatchRodEnergyAtReferenceCurvature) {
  // A chain on a circle of curvature kappa_ref stores the rod's EI kappa^2 / 2 per metre in its
  // bend springs (docs/mechanics.md), whatever the number of control points.
  for (int n : {101, 201, 401}) {
    const double kappa = 8.0, length = 0.5, ei = 1e-3;
    ModelParams p = StraightChain(n, length);
    p.bend_stiffness = ei;
    p.bend_reference_curvature = kappa;
    for (int i = 0; i < n; ++i) {
      const double a = kappa * length * i / (n - 1);
      p.initial_q.row(i) << std::sin(a) / kappa, (1.0 - std::cos(a)) / kappa, 0.0;
    }
    const Model model(p);
    const double bend = Evaluate(model, p.initial_q, Points::Zero(n, 3)).energies.bend;
    const double springs_length = (n - 2) * model.rest_segment_length();
    EXPECT_NEAR(bend / springs_length, 0.5 * ei * kappa * kappa, 0.01 * 0.5 * ei * kappa * kappa)
        << n;
  }
}

}  // namespace
}  // namespace viscera::mechanics
