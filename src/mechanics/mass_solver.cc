#include "mechanics/mass_solver.h"

namespace viscera::mechanics {

MassSolver::MassSolver(const Model& model) : model_(model) {
  if (model.params().mass_solver == MassSolverKind::kCholmod) {
    cholmod_ = std::make_unique<CholmodBandSolver>();
    cholmod_->Factor(model.mass_band());
  }
  const auto p = static_cast<Eigen::Index>(model.pins().size());
  pin_residual_.setZero(p, 3);
  pin_lambda_.setZero(p, 3);
}

void MassSolver::SolveInPlace(Points* b) {
  if (cholmod_) {
    cholmod_->SolveInPlace(b);
  } else {
    model_.mass_factor().SolveInPlace(b);
  }
}

void MassSolver::SolveConstrainedInPlace(Points* b) {
  SolveInPlace(b);
  const auto& pins = model_.pins();
  if (pins.empty()) return;
  for (size_t r = 0; r < pins.size(); ++r) {
    pin_residual_.row(r) = pins[r].at.w.transpose() * b->middleRows<4>(pins[r].at.first);
  }
  pin_lambda_.noalias() = model_.pin_schur_inverse().lazyProduct(pin_residual_);
  b->noalias() -= model_.pin_y().lazyProduct(pin_lambda_);
}

}  // namespace viscera::mechanics
