// ImplicitEulerIntegrator's tools (docs/tool-coupling.md): each tool's tip is
// three more unknowns of the implicit system,
//   [A  B] [dv  ]   [b  ]
//   [B' C] [dv_t] = [b_t],   C = m I + h D_tt + h^2 K_tt (3 x 3 per tool),
// B the tip-tube contacts' and grasps' coupling. The tips are eliminated by a Schur complement:
// (A - B C^-1 B') dv = b - B C^-1 b_t, then dv_t = C^-1 (b_t - B' dv). B has three columns per
// tool: the band solve takes them by Woodbury's identity, as it takes the rank-one term and pins.
#include <algorithm>

#include "mechanics/implicit_euler.h"
#include "mechanics/interactions.h"

namespace viscera::mechanics {

void ImplicitEulerIntegrator::ClearTipReleases() {
  tip_rounds_ = 0;
  friction_rounds_ = 0;
  if (interactions_ != nullptr) interactions_->ClearTipReleases();
}

bool ImplicitEulerIntegrator::HasTips(const State& state) const {
  return interactions_ != nullptr && interactions_->tips_in_solve() && !state.tools.empty();
}

void ImplicitEulerIntegrator::AddTipStiffness(const State& state) {
  // K v's rows of the tips and the links' part of the tube's: b = h (F - h K v) over both.
  const auto& rows = interactions_->tip_rows();
  for (int t = 0; t < num_tools_; ++t) {
    tip_kv_.segment<3>(3 * t) =
        rows[t].present ? Vec3(rows[t].k * state.tools[t].tip_velocity) : Vec3::Zero();
  }
  for (const TipLink& link : interactions_->tip_links()) {
    const Vec3& vt = state.tools[link.tool].tip_velocity;
    const Vec3 kvt = link.k * vt;
    Vec3 window = Vec3::Zero();
    for (int i = 0; i < 4; ++i) {
      kv_.row(link.first + i) += link.w[i] * kvt.transpose();
      window += link.w[i] * state.qd.row(link.first + i).transpose();
    }
    tip_kv_.segment<3>(3 * link.tool) += link.k.transpose() * window;  // K's block for the tip
  }
}

void ImplicitEulerIntegrator::ReduceTips(double h) {
  const auto& rows = interactions_->tip_rows();
  tip_c_.setZero();
  tip_c_inv_.setZero();
  for (int t = 0; t < num_tools_; ++t) {
    const TipRows& r = rows[t];
    if (!r.present) {
      tip_b_.segment<3>(3 * t).setZero();  // not yet placed: held (no unknowns to speak of)
      tip_c_.block<3, 3>(3 * t, 3 * t).setIdentity();
      tip_c_inv_.block<3, 3>(3 * t, 3 * t).setIdentity();
      continue;
    }
    tip_b_.segment<3>(3 * t) = h * (r.force - h * tip_kv_.segment<3>(3 * t));
    const Mat3 c = r.mass * Mat3::Identity() + h * r.d + h * h * r.k;
    tip_c_.block<3, 3>(3 * t, 3 * t) = c;
    tip_c_inv_.block<3, 3>(3 * t, 3 * t) = c.inverse();
  }
  tips_linked_ = !interactions_->tip_links().empty();
  if (!tips_linked_) return;
  tip_B_.setZero();
  int lo = n_, hi = 0;
  for (const TipLink& link : interactions_->tip_links()) {
    const Mat3 block = h * link.d + h * h * link.k;
    for (int i = 0; i < 4; ++i)
      tip_B_.block<3, 3>(3 * (link.first + i), 3 * link.tool) += link.w[i] * block;
    lo = std::min(lo, link.first);
    hi = std::max(hi, link.first + 4);
  }
  // B's rows are +0 outside the links' points. A product B z is row by row: its rows there
  // are left out. A product B' x is a dot product per column, summed in SIMD lanes by the row's
  // index: it starts at a multiple of eight rows and runs to the end, so that every lane and
  // the tail sum the same products in the same order (the +0 ones before add nothing).
  tip_row_begin_ = (3 * lo) / 8 * 8;
  tip_row_end_ = std::min(3 * n_, 3 * hi);
  tip_tmp_.noalias() = tip_c_inv_ * tip_b_;
  SubtractTipProduct(tip_tmp_, b_.data());
}

void ImplicitEulerIntegrator::TipTransposedProduct(const double* x, VecX* out) const {
  const Eigen::Index len = 3 * n_ - tip_row_begin_;
  out->noalias() = tip_B_.middleRows(tip_row_begin_, len).transpose() *
                   Eigen::Map<const VecX>(x + tip_row_begin_, len);
}

void ImplicitEulerIntegrator::SubtractTipProduct(const VecX& z, double* y) const {
  const Eigen::Index len = tip_row_end_ - tip_row_begin_;
  Eigen::Map<VecX>(y + tip_row_begin_, len).noalias() -= tip_B_.middleRows(tip_row_begin_, len) * z;
}

void ImplicitEulerIntegrator::PrepareTipCorrection() {
  // Woodbury: (P - B C^-1 B')^-1 = P^-1 + Y S^-1 Y',  Y = P^-1 B,  S = C - B' Y, P the
  // preconditioner with its rank-one term and pins (ApplyCorrections without this part yet).
  tip_woodbury_ = false;
  if (!tips_linked_) return;
  // B's columns are +0 above their tool's first linked point, and all +0 for a tool with no
  // link (its columns of Y are then +0 too, as the solve would give them): the band solves
  // start at that point, two columns at a time (each column's numbers those of its own solve).
  std::fill(tip_first_.begin(), tip_first_.end(), n_);
  for (const TipLink& link : interactions_->tip_links())
    tip_first_[link.tool] = std::min(tip_first_[link.tool], link.first);
  int pending = -1;
  for (int j = 0; j < 3 * num_tools_; ++j) {
    if (tip_first_[j / 3] >= n_) {
      tip_Y_.col(j).setZero();
      continue;
    }
    tip_Y_.col(j) = tip_B_.col(j);
    if (pending < 0) {
      pending = j;
      continue;
    }
    band_.SolveTwoInPlace(tip_Y_.col(pending).data(), tip_Y_.col(j).data(),
                          std::min(tip_first_[pending / 3], tip_first_[j / 3]));
    ApplyCorrections(tip_Y_.col(pending).data());
    ApplyCorrections(tip_Y_.col(j).data());
    pending = -1;
  }
  if (pending >= 0) {
    band_.SolveInPlace(tip_Y_.col(pending).data(), tip_first_[pending / 3]);
    ApplyCorrections(tip_Y_.col(pending).data());
  }
  tip_S_ = tip_c_;
  tip_S_.noalias() -= tip_B_.transpose() * tip_Y_;
  tip_S_ldlt_.compute(tip_S_);
  tip_woodbury_ = true;
}

void ImplicitEulerIntegrator::ApplyTipCorrection(double* x) const {
  Eigen::Map<VecX> y(x, 3 * n_);
  TipTransposedProduct(x, &tip_tmp_);
  tip_tmp2_ = tip_S_ldlt_.solve(tip_tmp_);
  y.noalias() += tip_Y_ * tip_tmp2_;
}

void ImplicitEulerIntegrator::SubtractTipSchur(const double* x, double* y) const {
  TipTransposedProduct(x, &tip_tmp_);
  tip_tmp2_.noalias() = tip_c_inv_ * tip_tmp_;
  SubtractTipProduct(tip_tmp2_, y);
}

bool ImplicitEulerIntegrator::SolveTips(double h, const Points& v, const double* dv,
                                        const State& state) {
  // dv_t = C^-1 (b_t - B' dv): the tips answer the tube's final velocities (impacts included).
  tip_tmp_ = tip_b_;
  if (tips_linked_) {
    TipTransposedProduct(dv, &tip_tmp2_);
    tip_tmp_ -= tip_tmp2_;
  }
  tip_dv_.noalias() = tip_c_inv_ * tip_tmp_;
  // Unlinked tips too: a tool pair that did not act at the start and that the solve drives the
  // tip into acts in the next solve (passed by, a tip at rest a hair apart ended 19 % of R deep).
  if (tip_rounds_ >= kMaxTipRounds) return false;
  for (int t = 0; t < num_tools_; ++t)
    tip_v_.segment<3>(3 * t) = state.tools[t].tip_velocity + tip_dv_.segment<3>(3 * t);
  return interactions_->ReviseTipContacts(h, v, dv, tip_v_);
}

void ImplicitEulerIntegrator::AdvanceTips(double h, const VecX* depth_dq, State* state) {
  // The depth constraints' position correction moves the tube by h A^-1 J' Λ; in the system with
  // the tips that is also -C^-1 B' of it for the tips (a sphere pushed back out of a wall carries
  // the tip pressing on it; left behind, the tip sank into it by that much at every sub-step).
  tip_tmp2_.setZero();
  if (depth_dq != nullptr && tips_linked_) {
    TipTransposedProduct(depth_dq->data(), &tip_tmp_);
    tip_tmp2_.noalias() = -tip_c_inv_ * tip_tmp_;
  }
  const auto& rows = interactions_->tip_rows();
  for (int t = 0; t < num_tools_; ++t) {
    if (!rows[t].present) continue;
    ToolState& ts = state->tools[t];
    ts.tip_velocity += tip_dv_.segment<3>(3 * t);
    ts.tip += h * (ts.tip_velocity + tip_tmp2_.segment<3>(3 * t));
    interactions_->TipAdvanced(t, h, &ts);
  }
}

}  // namespace viscera::mechanics
