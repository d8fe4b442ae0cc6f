#include "mechanics/friction_resolve.h"

#include <utility>

namespace viscera::mechanics {

FrictionResolve::FrictionResolve(int points, Interactions* interactions, bool stick_slip,
                                 std::function<void(double*)> band_inverse)
    : interactions_(interactions), band_inverse_(std::move(band_inverse)) {
  b_evaluated_.setZero(3 * points);
  dv_solved_.setZero(3 * points);
  if (stick_slip) changes_.reserve(static_cast<size_t>(interactions_->chain().size()) * 8);
}

bool FrictionResolve::TakeRevisions(double h_eff, double stiffness, double history, VecX* b,
                                    Eigen::Ref<VecX> dv, State* state) {
  if (!changed_) b_evaluated_ = *b;
  if (!interactions_->ApplyFrictionRevisions(&changes_)) return false;
  changed_ = true;
  stiffness_ = stiffness;
  damping_ = h_eff;
  // b = ĥ (F - ĥ K v) + μ (M Δv - ĥ K Δq): each pair's change of F and K.
  const bool multistep = history > 0.0;
  *b = b_evaluated_;
  for (const StickSlipFriction::Change& c : changes_) {
    Vec3 moved = h_eff * c.Motion(state->qd.data());
    if (multistep) moved += history * c.Motion(state->last_dq.data());
    c.Scatter(h_eff * (c.force - c.k * moved), b->data());
  }
  // CG from the last solve's answer: its correction is that less the band's answer to the new b.
  dv_solved_ = dv;
  dv = *b;
  band_inverse_(dv.data());
  state->cg_correction = dv_solved_ - dv;
  ++resolves_;
  return true;
}

}  // namespace viscera::mechanics
