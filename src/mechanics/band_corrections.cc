#include "mechanics/band_corrections.h"

namespace viscera::mechanics {

BandCorrections::BandCorrections(const Model& model)
    : model_(model), n_(model.num_points()), pins_(static_cast<int>(model.pins().size())) {
  columns_.setZero(3 * n_, 2 + 3 * pins_);
  schur_.setZero(3 * pins_, 3 * pins_);
  pin_rhs_.setZero(3 * pins_);
  pin_lambda_.setZero(3 * pins_);
}

void BandCorrections::Load(const VecX& b, const Points& u) {
  columns_.col(0) = b;
  columns_.col(1) = Eigen::Map<const VecX>(u.data(), 3 * n_);
  for (int p = 0; p < pins_; ++p) {
    const CurvePoint& at = model_.pins()[p].at;
    for (int axis = 0; axis < 3; ++axis) {
      auto col = columns_.col(2 + 3 * p + axis);
      col.setZero();
      for (int a = 0; a < 4; ++a) col(3 * (at.first + a) + axis) = at.w(a);
    }
  }
}

void BandCorrections::Prepare(const Points& u_points) {
  // Sherman-Morrison for w u u^T: z = A^-1 u is column 1.
  if (w_ > 0.0) {
    Eigen::Map<const VecX> u(u_points.data(), 3 * n_);
    denom_ = 1.0 + w_ * u.dot(columns_.col(1));
    for (Eigen::Index k = 2; k < columns_.cols(); ++k)
      columns_.col(k) -= (w_ * u.dot(columns_.col(k)) / denom_) * columns_.col(1);
  }
  // Pins: S = G Y with Y = A^-1 G^T (columns 2..), factored once per sub-step.
  if (pins_ == 0) return;
  const auto y = columns_.rightCols(3 * pins_);
  for (int r = 0; r < 3 * pins_; ++r) {
    const CurvePoint& at = model_.pins()[r / 3].at;
    const int axis = r % 3;
    for (int col = 0; col < 3 * pins_; ++col) {
      double gy = 0.0;
      for (int a = 0; a < 4; ++a) gy += at.w(a) * y(3 * (at.first + a) + axis, col);
      schur_(r, col) = gy;
    }
  }
  schur_ldlt_.compute(schur_);
}

void BandCorrections::Apply(double* x, const Points& u_points) {
  Eigen::Map<VecX> dv(x, 3 * n_);
  // (A + w u u^T)^-1 x = A^-1 x - z (w u.A^-1 x) / (1 + w u.z), z = A^-1 u.
  if (w_ > 0.0) {
    Eigen::Map<const VecX> u(u_points.data(), 3 * n_);
    dv -= (w_ * u.dot(dv) / denom_) * columns_.col(1);
  }
  // Pins: dv = x - Y S^-1 G x.
  if (pins_ == 0) return;
  for (int r = 0; r < 3 * pins_; ++r) {
    const CurvePoint& at = model_.pins()[r / 3].at;
    double gx = 0.0;
    for (int a = 0; a < 4; ++a) gx += at.w(a) * dv(3 * (at.first + a) + r % 3);
    pin_rhs_(r) = gx;
  }
  pin_lambda_ = schur_ldlt_.solve(pin_rhs_);
  dv.noalias() -= columns_.rightCols(3 * pins_).lazyProduct(pin_lambda_);
}

}  // namespace viscera::mechanics
