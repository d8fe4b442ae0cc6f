#include "mechanics/implicit_euler.h"

#include <algorithm>

#include "mechanics/mass_solver.h"


namespace viscera::mechanics {

ImplicitEulerIntegrator::ImplicitEulerIntegrator(const Model& model, Interactions* interactions)
    : model_(model),
      interactions_(interactions),
      n_(model.num_points()),
      num_pins_(static_cast<int>(model.pins().size())),
      use_cholmod_(model.params().linear_solver == LinearSolverKind::kCholmod),
      system_(model.num_points()),
      solver_(&common_),
      solve_work_(&common_) {
  scratch_.Resize(n_);
  jac_.Resize(n_);
  force_.setZero(n_, 3);
  kv_.setZero(n_, 3);
  rhs_.setZero(3 * n_, 2 + 3 * num_pins_);
  schur_.setZero(3 * num_pins_, 3 * num_pins_);
  pin_rhs_.setZero(3 * num_pins_);
  pin_lambda_.setZero(3 * num_pins_);
  if (use_cholmod_) BuildPattern();
}

void ImplicitEulerIntegrator::BuildPattern() {
  // Upper triangle of the 3N x 3N block band, column by column, rows sorted.
  const int dim = 3 * n_;
  std::vector<int> col_ptr(dim + 1, 0), row_index;
  slot_.assign(static_cast<size_t>(n_) * BlockBand::kWidth * 9, -1);
  for (int j = 0; j < n_; ++j) {
    for (int beta = 0; beta < 3; ++beta) {
      const int col = 3 * j + beta;
      for (int i = std::max(0, j - 3); i <= j; ++i) {
        for (int alpha = 0; alpha < 3; ++alpha) {
          const int row = 3 * i + alpha;
          if (row > col) continue;
          slot_[((static_cast<size_t>(i) * BlockBand::kWidth + (j - i)) * 3 + alpha) * 3 + beta] =
              static_cast<int>(row_index.size());
          row_index.push_back(row);
        }
      }
      col_ptr[col + 1] = static_cast<int>(row_index.size());
    }
  }
  solver_.SetPattern(dim, col_ptr, row_index);
}

void ImplicitEulerIntegrator::AssembleSystem(double h) {
  const Band& m = model_.mass_band();
  const double h2 = h * h;
  for (int i = 0; i < n_; ++i) {
    for (int d = 0; d < BlockBand::kWidth && i + d < n_; ++d) {
      Mat3& block = system_.block(i, d);
      block = h * jac_.damping.block(i, d) + h2 * jac_.stiffness.block(i, d);
      block.diagonal().array() += m(i, d);
    }
  }
}

bool ImplicitEulerIntegrator::FactorSystem() {
  if (!use_cholmod_) return band_factor_.Factor(system_);
  double* values = solver_.values();
  for (int i = 0; i < n_; ++i) {
    for (int d = 0; d < BlockBand::kWidth && i + d < n_; ++d) {
      const Mat3& block = system_.block(i, d);
      const int* s = &slot_[(static_cast<size_t>(i) * BlockBand::kWidth + d) * 9];
      for (int e = 0; e < 9; ++e) {
        if (s[e] >= 0) values[s[e]] = block(e / 3, e % 3);
      }
    }
  }
  return solver_.Factorize();
}

void ImplicitEulerIntegrator::SolveColumns() {
  const Eigen::Index cols = rhs_.cols();
  if (use_cholmod_) {
    solver_.SolveInPlace(rhs_.data(), static_cast<int>(cols), &solve_work_);
    return;
  }
  for (Eigen::Index k = 0; k < cols; ++k) band_factor_.SolveInPlace(rhs_.col(k).data());
}

void ImplicitEulerIntegrator::Advance(std::span<const PointLoad> loads, double h, State* state) {
  Points& q = state->q;
  Points& v = state->qd;
  ComputeForces(model_, q, v, loads, &scratch_, &force_, nullptr, &jac_, interactions_);

  // r = h (F - h K v), K including the rank-one part c u (u . v).
  jac_.stiffness.Multiply(v, &kv_);
  const double c = jac_.rank1_coeff;
  if (c > 0.0) kv_ += (c * (jac_.rank1_u.array() * v.array()).sum()) * jac_.rank1_u;
  Eigen::Map<const VecX> force_flat(force_.data(), 3 * n_);
  Eigen::Map<const VecX> kv_flat(kv_.data(), 3 * n_);
  rhs_.col(0) = h * (force_flat - h * kv_flat);
  rhs_.col(1) = Eigen::Map<const VecX>(jac_.rank1_u.data(), 3 * n_);
  for (int p = 0; p < num_pins_; ++p) {
    const CurvePoint& at = model_.pins()[p].at;
    for (int axis = 0; axis < 3; ++axis) {
      auto col = rhs_.col(2 + 3 * p + axis);
      col.setZero();
      for (int a = 0; a < 4; ++a) col(3 * (at.first + a) + axis) = at.w(a);
    }
  }

  AssembleSystem(h);
  if (!FactorSystem()) {
    // Cannot happen for M + hD + h^2 K with K, D clamped PSD; count it and take an explicit
    // step rather than produce garbage.
    ++factorization_failures_;
    MassSolver fallback(model_);
    fallback.SolveConstrainedInPlace(&force_);  // allocates, but this path is an error
    v += h * force_;
    q += h * v;
    return;
  }
  SolveColumns();
  const Eigen::Index cols = rhs_.cols();

  // Sherman-Morrison: (A + w u u^T)^-1 x = A^-1 x - z (w u.A^-1 x) / (1 + w u.z), z = A^-1 u.
  const double w = h * h * c;
  if (w > 0.0) {
    Eigen::Map<const VecX> u(jac_.rank1_u.data(), 3 * n_);
    const double denom = 1.0 + w * u.dot(rhs_.col(1));
    for (Eigen::Index k = 0; k < cols; ++k) {
      if (k == 1) continue;
      const double coeff = w * u.dot(rhs_.col(k)) / denom;
      rhs_.col(k) -= coeff * rhs_.col(1);
    }
  }

  // Pins: dv = x - Y S^-1 G x with Y = A^-1 G^T, S = G Y (G's rows are rhs_ columns 2..).
  auto dv = rhs_.col(0);
  if (num_pins_ > 0) {
    const auto y = rhs_.rightCols(3 * num_pins_);
    for (int r = 0; r < 3 * num_pins_; ++r) {
      const CurvePoint& at = model_.pins()[r / 3].at;
      const int axis = r % 3;
      double gx = 0.0;
      for (int a = 0; a < 4; ++a) gx += at.w(a) * dv(3 * (at.first + a) + axis);
      pin_rhs_(r) = gx;
      for (int col = 0; col < 3 * num_pins_; ++col) {
        double gy = 0.0;
        for (int a = 0; a < 4; ++a) gy += at.w(a) * y(3 * (at.first + a) + axis, col);
        schur_(r, col) = gy;
      }
    }
    schur_ldlt_.compute(schur_);
    pin_lambda_ = schur_ldlt_.solve(pin_rhs_);
    dv.noalias() -= y.lazyProduct(pin_lambda_);
  }

  Eigen::Map<VecX>(v.data(), 3 * n_) += dv;
  q += h * v;
}

}  // namespace viscera::mechanics
