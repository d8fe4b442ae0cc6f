#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "mechanics/forces.h"
#include "mechanics/stability.h"
#include "mechanics/step.h"
#include "test_models.h"

namespace viscera::mechanics {
namespace {

using testing::Perturbed;
using testing::StraightChain;

State Simulate(const Model& model, double seconds, State state) {
  Workspace ws(model);
  const int steps = static_cast<int>(std::lround(seconds * model.params().rate_hz));
  for (int k = 0; k < steps; ++k) Step(model, {}, &state, &ws);
  return state;
}

double TotalEnergy(const Model& model, const State& s) {
  return ComputeEnergies(model, s.q, s.qd).total();
}

TEST(Integrators, Rk4FreeFallIsExact) {
  ModelParams p = StraightChain(20);
  p.gravity = Vec3(0.0, 0.0, -9.81);
  p.stretch_stiffness = 100.0;
  p.continuous_stretch = 1.0;
  const Model probe(p);
  p.substeps = EstimateStability(probe, InitialState(probe)).stable_substeps;
  const Model model(p);
  const State end = Simulate(model, 1.0, InitialState(model));
  for (int i = 0; i < 20; ++i) {
    const Vec3 expected = p.initial_q.row(i).transpose() + 0.5 * p.gravity;
    EXPECT_LT((end.q.row(i).transpose() - expected).norm(), 1e-9);
    EXPECT_LT((end.qd.row(i).transpose() - p.gravity).norm(), 1e-9);
  }
}

TEST(Integrators, ImplicitEulerFreeFallVelocityIsExact) {
  for (ImplicitScheme scheme : {ImplicitScheme::kBackwardEuler, ImplicitScheme::kBdf2}) {
    ModelParams p = StraightChain(20);
    p.gravity = Vec3(0.0, 0.0, -9.81);
    p.stretch_stiffness = 100.0;
    p.integrator = IntegratorKind::kImplicitEuler;
    p.implicit_scheme = scheme;
    const Model model(p);
    const State end = Simulate(model, 1.0, InitialState(model));
    // Both: v_k = k h g exactly. Backward Euler moves q by h v_k (z_k = h^2 g k (k + 1) / 2); BDF2,
    // after a first backward Euler sub-step, by Δz_k = Δz_k-1 / 3 + (2h/3) v_k, which tends to the
    // exact h^2 g (k - 1/2).
    const double h = model.step_size();
    const int k = 100;
    double z = 0.0, dz = 0.0;
    for (int j = 1; j <= k; ++j) {
      const double vj = j * h * p.gravity.z();
      dz = j == 1 || scheme == ImplicitScheme::kBackwardEuler ? h * vj
                                                              : dz / 3.0 + 2.0 * h / 3.0 * vj;
      z += dz;
    }
    if (scheme == ImplicitScheme::kBackwardEuler) {
      EXPECT_NEAR(z, 0.5 * h * h * p.gravity.z() * k * (k + 1), 1e-12);
    }
    for (int i = 0; i < 20; ++i) {
      EXPECT_LT((end.qd.row(i).transpose() - p.gravity).norm(), 1e-9);
      EXPECT_NEAR(end.q(i, 2), z, 1e-9);
    }
  }
}

TEST(Integrators, Rk4ConservesEnergyOfUndampedStretchedSpline) {
  // Stretched 10 % and bent a little, every conservative term on, no damping, no gravity.
  ModelParams p = StraightChain(30, 1.0, 1.1);
  p.initial_q = Perturbed(p.initial_q, 0.01, 21);
  p.stretch_stiffness = 40.0;
  p.bend_stiffness = 1e-4;
  p.continuous_stretch = 0.5;
  p.attachments.push_back({0.5, std::nullopt, 20.0, 0.0, 0.0});
  p.rate_hz = 100.0;
  // RK4 damps a mode by about (h omega)^6 / 72 of its energy per step: conservation needs
  // h omega << 1, not just stability. h omega_max = 0.05 here.
  const Model probe(p);
  const double omega = EstimateStability(probe, InitialState(probe)).omega_max;
  p.substeps = static_cast<int>(std::ceil(omega * probe.step_size() / 0.05));
  const Model model(p);
  const State start = InitialState(model);
  const double e0 = TotalEnergy(model, start);
  State s = start;
  Workspace ws(model);
  double worst = 0.0;
  for (int k = 0; k < 200; ++k) {  // 2 s, many periods of the stiff modes
    Step(model, {}, &s, &ws);
    worst = std::max(worst, std::abs(TotalEnergy(model, s) - e0));
  }
  EXPECT_GT(ComputeEnergies(model, s.q, s.qd).kinetic, 0.01 * e0);  // it really moves
  EXPECT_LT(worst, 1e-5 * e0) << "substeps " << p.substeps;         // stated tolerance: 1e-5
}

TEST(Integrators, StabilityEstimateMatchesADenseEigensolver) {
  for (int n : {30, 120}) {
    ModelParams p = StraightChain(n, 1.0, 1.05);
    p.initial_q = Perturbed(p.initial_q, 0.002, 9);
    p.stretch_stiffness = 200.0;
    p.bend_stiffness = 1e-4;
    p.continuous_stretch = 1.0;
    p.damping = 0.5;
    p.pinned = {0.0, 0.7};
    const Model model(p);
    // Dense generalized eigenproblem K x = lambda M x on the pins' null space.
    StretchScratch scratch;
    scratch.Resize(n);
    ForceJacobians jac;
    jac.Resize(n);
    Points f(n, 3);
    ComputeForces(model, p.initial_q, Points::Zero(n, 3), {}, &scratch, &f, nullptr, &jac);
    MatX k = MatX::Zero(3 * n, 3 * n), m = MatX::Zero(3 * n, 3 * n);
    for (int i = 0; i < n; ++i) {
      for (int d = 0; d < 4 && i + d < n; ++d) {
        k.block<3, 3>(3 * i, 3 * (i + d)) += jac.stiffness.block(i, d);
        m.block<3, 3>(3 * i, 3 * (i + d)) += model.mass_band()(i, d) * Mat3::Identity();
        if (d) {
          k.block<3, 3>(3 * (i + d), 3 * i) += jac.stiffness.block(i, d).transpose();
          m.block<3, 3>(3 * (i + d), 3 * i) += model.mass_band()(i, d) * Mat3::Identity();
        }
      }
    }
    const Eigen::Map<const VecX> u(jac.rank1_u.data(), 3 * n);
    k += jac.rank1_coeff * u * u.transpose();
    MatX g = MatX::Zero(3 * model.pins().size(), 3 * n);
    for (size_t r = 0; r < model.pins().size(); ++r) {
      for (int a = 0; a < 4; ++a) {
        for (int axis = 0; axis < 3; ++axis)
          g(3 * r + axis, 3 * (model.pins()[r].at.first + a) + axis) = model.pins()[r].at.w(a);
      }
    }
    const MatX z = Eigen::FullPivLU<MatX>(g).kernel();
    Eigen::GeneralizedSelfAdjointEigenSolver<MatX> eig(z.transpose() * k * z,
                                                       z.transpose() * m * z);
    const double omega = std::sqrt(eig.eigenvalues().maxCoeff());
    EXPECT_NEAR(EstimateStability(model, InitialState(model)).omega_max, omega, 0.01 * omega) << n;
  }
}

TEST(Integrators, StabilityEstimatePredictsRk4BlowUp) {
  ModelParams p = StraightChain(40, 1.0, 1.05);
  p.initial_q = Perturbed(p.initial_q, 0.002, 5);
  p.stretch_stiffness = 500.0;
  const Model probe(p);
  const StabilityEstimate est = EstimateStability(probe, InitialState(probe));
  ASSERT_GT(est.stable_substeps, 4);

  p.substeps = est.stable_substeps;
  const Model stable(p);
  const State a = Simulate(stable, 1.0, InitialState(stable));
  EXPECT_EQ(a.nonfinite_resets, 0);
  EXPECT_LT(TotalEnergy(stable, a), 1.01 * TotalEnergy(stable, InitialState(stable)));

  p.substeps = est.stable_substeps / 2;  // h * rate about 5.6: far outside the region
  const Model unstable(p);
  const State b = Simulate(unstable, 1.0, InitialState(unstable));
  EXPECT_TRUE(b.nonfinite_resets > 0 ||
              TotalEnergy(unstable, b) > 10.0 * TotalEnergy(unstable, InitialState(unstable)));
}

ModelParams GentleSwing(IntegratorKind kind) {
  // A soft chain pinned at its start swings down under gravity.
  ModelParams p = StraightChain(25, 1.0);
  p.gravity = Vec3(0.0, 0.0, -9.81);
  p.stretch_stiffness = 30.0;
  p.continuous_stretch = 0.2;
  p.damping = 0.2;
  p.pinned = {0.0};
  p.integrator = kind;
  p.rate_hz = 1000.0;
  p.substeps = kind == IntegratorKind::kRk4 ? 4 : 2;
  return p;
}

TEST(Integrators, Rk4AndImplicitEulerAgreeOnAGentleMotion) {
  const Model rk4(GentleSwing(IntegratorKind::kRk4));
  const Model implicit(GentleSwing(IntegratorKind::kImplicitEuler));
  const State a = Simulate(rk4, 0.3, InitialState(rk4));
  const State b = Simulate(implicit, 0.3, InitialState(implicit));
  const double travelled = (a.q.row(24) - rk4.params().initial_q.row(24)).norm();
  EXPECT_GT(travelled, 0.2);  // the tip really swung
  // First-order implicit Euler at h = 0.5 ms: within 1 % of the chain length.
  EXPECT_LT((a.q - b.q).rowwise().norm().maxCoeff(), 0.01);
}

TEST(Integrators, BlockBandAndCholmodSolveTheSameImplicitSystem) {
  ModelParams p = GentleSwing(IntegratorKind::kImplicitEuler);
  p.bend_stiffness = 1e-4;
  p.spring_damping = 1.0;
  p.pinned = {0.0, 0.5};
  p.attachments.push_back({1.0, Vec3(1.2, 0.0, -0.3), 20.0, 0.5, 0.0});
  p.linear_solver = LinearSolverKind::kBlockBand;
  const Model band(p);
  p.linear_solver = LinearSolverKind::kCholmod;
  const Model cholmod(p);
  const State a = Simulate(band, 0.3, InitialState(band));
  const State b = Simulate(cholmod, 0.3, InitialState(cholmod));
  EXPECT_GT((a.q - p.initial_q).norm(), 0.05);
  EXPECT_LT((a.q - b.q).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((a.qd - b.qd).cwiseAbs().maxCoeff(), 1e-8);
}

TEST(Integrators, PinsHoldExactlyInBothIntegrators) {
  for (IntegratorKind kind : {IntegratorKind::kRk4, IntegratorKind::kImplicitEuler}) {
    ModelParams p = GentleSwing(kind);
    p.pinned = {0.0, 0.37, 1.0};
    const Model model(p);
    const State end = Simulate(model, 0.5, InitialState(model));
    for (const Pin& pin : model.pins()) {
      EXPECT_LT((Model::Evaluate(pin.at, end.q) - pin.position).norm(), 1e-10);
    }
    EXPECT_GT((end.q - p.initial_q).norm(), 0.01);  // the free parts moved
  }
}

// Analytic catenary between (-d/2, 0) and (d/2, 0) with arc length L, lowest point below:
// z(x) = a cosh(x / a) - a cosh(d / 2a), with 2 a sinh(d / 2a) = L.
struct Catenary {
  double a, d;
  Catenary(double length, double span) : d(span) {
    double lo = 1e-3, hi = 100.0;  // 2a sinh(d/2a) decreases in a
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (2.0 * mid * std::sinh(d / (2.0 * mid)) > length ? lo : hi) = mid;
    }
    a = 0.5 * (lo + hi);
  }
  // Point at arc length s from the left end.
  Eigen::Vector2d At(double s) const {
    const double x = a * std::asinh(s / a - std::sinh(d / (2.0 * a)));
    return {x, a * std::cosh(x / a) - a * std::cosh(d / (2.0 * a))};
  }
};

TEST(Integrators, PinnedSplineSettlesIntoTheCatenary) {
  const int n = 41;
  const double length = 1.0, span = 0.8;
  ModelParams p = StraightChain(n, length);
  // Start as a V of the right length between the pins.
  const double depth = std::sqrt(0.25 * length * length - 0.25 * span * span);
  for (int i = 0; i < n; ++i) {
    const double f = static_cast<double>(i) / (n - 1);
    const double x = -span / 2 + span * f;
    p.initial_q.row(i) << x, 0.0, -depth * (1.0 - std::abs(2.0 * f - 1.0));
  }
  p.gravity = Vec3(0.0, 0.0, -9.81);
  p.stretch_stiffness = 5000.0;  // nearly inextensible: strain ~ 1e-3
  p.damping = 3.0;
  p.spring_damping = 20.0;
  p.pinned = {0.0, 1.0};
  p.integrator = IntegratorKind::kImplicitEuler;
  const Model model(p);
  const State end = Simulate(model, 15.0, InitialState(model));
  EXPECT_LT(end.qd.cwiseAbs().maxCoeff(), 1e-4);  // settled

  const Catenary cat(length, span);
  double worst = 0.0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d expected = cat.At(length * i / (n - 1));
    const Eigen::Vector2d got(end.q(i, 0), end.q(i, 2));
    worst = std::max(worst, (got - expected).norm());
    EXPECT_NEAR(end.q(i, 1), 0.0, 1e-9);
  }
  // Tolerance: 0.3 % of the length (elastic stretch and spline discretization).
  EXPECT_LT(worst, 0.003 * length);
}

}  // namespace
}  // namespace viscera::mechanics
