#include "mechanics/tip_schur.h"

#include <algorithm>

namespace viscera::mechanics {

TipSchur::TipSchur(int points, int tools, Interactions* interactions)
    : n_(points), num_tools_(tools), interactions_(interactions) {
  B_.setZero(3 * n_, 3 * num_tools_);
  Y_.setZero(3 * n_, 3 * num_tools_);
  first_.assign(num_tools_, n_);
  for (MatX* m : {&c_, &c_inv_, &S_}) m->setZero(3 * num_tools_, 3 * num_tools_);
  for (VecX* v : {&b_, &kv_, &dv_, &v_, &tmp_, &tmp2_}) v->setZero(3 * num_tools_);
}

bool TipSchur::Present(const State& state) const {
  return interactions_ != nullptr && interactions_->tips_in_solve() && !state.tools.empty();
}

void TipSchur::AddStiffness(const State& state, Points* kv) {
  // K v's rows of the tips and the links' part of the tube's: b = h (F - h K v) over both.
  const auto& rows = interactions_->tip_rows();
  for (int t = 0; t < num_tools_; ++t) {
    kv_.segment<3>(3 * t) =
        rows[t].present ? Vec3(rows[t].k * state.tools[t].tip_velocity) : Vec3::Zero();
  }
  for (const TipLink& link : interactions_->tip_links()) {
    const Vec3& vt = state.tools[link.tool].tip_velocity;
    const Vec3 kvt = link.k * vt;
    Vec3 window = Vec3::Zero();
    for (int i = 0; i < 4; ++i) {
      kv->row(link.first + i) += link.w[i] * kvt.transpose();
      window += link.w[i] * state.qd.row(link.first + i).transpose();
    }
    kv_.segment<3>(3 * link.tool) += link.k.transpose() * window;  // K's block for the tip
  }
}

void TipSchur::Reduce(double h, VecX* b) {
  const auto& rows = interactions_->tip_rows();
  c_.setZero();
  c_inv_.setZero();
  for (int t = 0; t < num_tools_; ++t) {
    const TipRows& r = rows[t];
    if (!r.present) {
      b_.segment<3>(3 * t).setZero();  // not yet placed: held (no unknowns to speak of)
      c_.block<3, 3>(3 * t, 3 * t).setIdentity();
      c_inv_.block<3, 3>(3 * t, 3 * t).setIdentity();
      continue;
    }
    b_.segment<3>(3 * t) = h * (r.force - h * kv_.segment<3>(3 * t));
    const Mat3 c = r.mass * Mat3::Identity() + h * r.d + h * h * r.k;
    c_.block<3, 3>(3 * t, 3 * t) = c;
    c_inv_.block<3, 3>(3 * t, 3 * t) = c.inverse();
  }
  linked_ = !interactions_->tip_links().empty();
  if (!linked_) return;
  B_.setZero();
  int lo = n_, hi = 0;
  for (const TipLink& link : interactions_->tip_links()) {
    const Mat3 block = h * link.d + h * h * link.k;
    for (int i = 0; i < 4; ++i)
      B_.block<3, 3>(3 * (link.first + i), 3 * link.tool) += link.w[i] * block;
    lo = std::min(lo, link.first);
    hi = std::max(hi, link.first + 4);
  }
  // B's rows are +0 outside the links' points. A product B z is row by row: its rows there
  // are left out. A product B' x is a dot product per column, summed in SIMD lanes by the row's
  // index: it starts at a multiple of eight rows and runs to the end, so that every lane and
  // the tail sum the same products in the same order (the +0 ones before add nothing).
  row_begin_ = (3 * lo) / 8 * 8;
  row_end_ = std::min(3 * n_, 3 * hi);
  tmp_.noalias() = c_inv_ * b_;
  SubtractProduct(tmp_, b->data());
}

void TipSchur::TransposedProduct(const double* x, VecX* out) const {
  const Eigen::Index len = 3 * n_ - row_begin_;
  out->noalias() =
      B_.middleRows(row_begin_, len).transpose() * Eigen::Map<const VecX>(x + row_begin_, len);
}

void TipSchur::SubtractProduct(const VecX& z, double* y) const {
  const Eigen::Index len = row_end_ - row_begin_;
  Eigen::Map<VecX>(y + row_begin_, len).noalias() -= B_.middleRows(row_begin_, len) * z;
}

void TipSchur::LoadColumns(std::vector<double*>* columns, std::vector<int>* first) {
  // Woodbury: (P - B C^-1 B')^-1 = P^-1 + Y S^-1 Y',  Y = P^-1 B,  S = C - B' Y, P the
  // preconditioner with its rank-one term and pins (ApplyCorrections without this part yet).
  // B's columns are +0 above their tool's first linked point, and all +0 for a tool with no
  // link (its columns of Y are then +0 too, as the solve would give them): the band solves
  // start at that point (each column's numbers those of its own solve).
  woodbury_ = false;
  if (!linked_) return;
  std::fill(first_.begin(), first_.end(), n_);
  for (const TipLink& link : interactions_->tip_links())
    first_[link.tool] = std::min(first_[link.tool], link.first);
  for (int j = 0; j < 3 * num_tools_; ++j) {
    if (first_[j / 3] >= n_) {
      Y_.col(j).setZero();
      continue;
    }
    Y_.col(j) = B_.col(j);
    columns->push_back(Y_.col(j).data());
    first->push_back(first_[j / 3]);
  }
}

void TipSchur::PrepareCorrection(const std::function<void(double*)>& corrections) {
  if (!linked_) return;
  for (int j = 0; j < 3 * num_tools_; ++j) {
    if (first_[j / 3] < n_) corrections(Y_.col(j).data());
  }
  S_ = c_;
  S_.noalias() -= B_.transpose() * Y_;
  S_ldlt_.compute(S_);
  woodbury_ = true;
}

void TipSchur::ApplyCorrection(double* x) const {
  Eigen::Map<VecX> y(x, 3 * n_);
  TransposedProduct(x, &tmp_);
  tmp2_ = S_ldlt_.solve(tmp_);
  y.noalias() += Y_ * tmp2_;
}

void TipSchur::SubtractSchur(const double* x, double* y) const {
  TransposedProduct(x, &tmp_);
  tmp2_.noalias() = c_inv_ * tmp_;
  SubtractProduct(tmp2_, y);
}

bool TipSchur::Solve(double h, const Points& v, const double* dv, const State& state) {
  // dv_t = C^-1 (b_t - B' dv): the tips answer the tube's final velocities (impacts included).
  tmp_ = b_;
  if (linked_) {
    TransposedProduct(dv, &tmp2_);
    tmp_ -= tmp2_;
  }
  dv_.noalias() = c_inv_ * tmp_;
  // Unlinked tips too: a tool pair that did not act at the start and that the solve drives the
  // tip into acts in the next solve (passed by, a tip at rest a hair apart ended 19 % of R deep).
  if (rounds_ >= kMaxRounds) return false;
  for (int t = 0; t < num_tools_; ++t)
    v_.segment<3>(3 * t) = state.tools[t].tip_velocity + dv_.segment<3>(3 * t);
  return interactions_->ReviseTipContacts(h, v, dv, v_);
}

void TipSchur::Advance(double h, const VecX* depth_dq, State* state) {
  // The depth constraints' position correction moves the tube by h A^-1 J' Λ; in the system with
  // the tips that is also -C^-1 B' of it for the tips (a sphere pushed back out of a wall carries
  // the tip pressing on it; left behind, the tip sank into it by that much at every sub-step).
  tmp2_.setZero();
  if (depth_dq != nullptr && linked_) {
    TransposedProduct(depth_dq->data(), &tmp_);
    tmp2_.noalias() = -c_inv_ * tmp_;
  }
  const auto& rows = interactions_->tip_rows();
  for (int t = 0; t < num_tools_; ++t) {
    if (!rows[t].present) continue;
    ToolState& ts = state->tools[t];
    ts.tip_velocity += dv_.segment<3>(3 * t);
    ts.tip += h * (ts.tip_velocity + tmp2_.segment<3>(3 * t));
    interactions_->TipAdvanced(t, h, &ts);
  }
}

}  // namespace viscera::mechanics
