#include "mechanics/end_constraints.h"

#include <algorithm>
#include <utility>

#include "mechanics/banded_cholesky.h"
#include "mechanics/contact_impulses.h"

namespace viscera::mechanics {
namespace {

// The set of contacts grows until the impulses leave no other pair beyond its bound; rarely
// past two rounds.
constexpr int kMaxImpactRounds = 4;

// The tube's mass, 1^T M 1 (the sum of M's entries, from its upper band storage).
double TotalMass(const Band& mass) {
  const auto n = mass.rows();
  double total = 0.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    for (int d = 0; d <= kHalfBand && j + d < n; ++d) total += (d == 0 ? 1.0 : 2.0) * mass(j, d);
  }
  return total;
}

}  // namespace

EndConstraints::EndConstraints(const Model& model, Interactions* interactions,
                               std::function<void(double*)> band_inverse)
    : model_(model),
      interactions_(interactions),
      n_(model.num_points()),
      band_inverse_(std::move(band_inverse)) {
  check_.setZero(n_, 3);  // Needed may be its first use, in any sub-step
}

double EndConstraints::ContactSpeed(const ImpactLimiter::Contact& c, const double* x) const {
  const auto& spheres = interactions_->chain().spheres();
  Vec3 u = Vec3::Zero();
  const collision::Sphere& sa = spheres[c.a];
  for (int k = 0; k < 4; ++k) u += sa.w[k] * Eigen::Map<const Vec3>(x + 3 * (sa.first + k));
  if (c.b >= 0) {
    const collision::Sphere& sb = spheres[c.b];
    for (int k = 0; k < 4; ++k) u -= sb.w[k] * Eigen::Map<const Vec3>(x + 3 * (sb.first + k));
  }
  return c.normal.dot(u);
}

bool EndConstraints::Solve(Interactions::EndConstraint kind, double h, const Points& base,
                           VecX* delta) {
  // The constrained step: A dv = b + J^T Λ with Λ ≥ 0 the least impulses that bring every
  // selected pair's end depth within its bound (J (v + dv) ≥ target): the implicit step's
  // quadratic model minimized under those constraints. With v + A^-1 b = base already solved, Λ
  // solves the LCP on the Delassus matrix J A^-1 J^T, whose columns A^-1 J_i^T each take one
  // solve of the band system (with its rank-one term and pins). The band holds self pairs as an
  // upper bound of the exact matrix; refining A^-1 J^T Λ by CG on the exact one (as the solve
  // does) broke the LCP's balance (opposed impulses on a squeezed sphere no longer cancel) and
  // blew up, so the impulses act through the band system, which is what their Λ was solved on.
  check_ = base;
  const auto& spheres = interactions_->chain().spheres();
  const double immobile = 1e-9 / model_.segment_mass();
  Eigen::Index solved = 0;
  delassus_.Reset();  // the columns are solved again below
  bool any = false;
  for (int round = 0; round < kMaxImpactRounds; ++round) {
    if (!interactions_->GatherEndConstraints(kind, h, check_, base, round == 0, &set_)) break;
    const auto c = static_cast<Eigen::Index>(set_.size());
    if (columns_.cols() < c)
      columns_.conservativeResize(3 * n_, std::max<Eigen::Index>(c, 2 * columns_.cols()));
    if (lambda_.size() < c) {
      const Eigen::Index room = std::max<Eigen::Index>(c, 2 * lambda_.size());
      lambda_.resize(room);
      speed_.resize(room);
      target_.resize(room);
    }
    // The new contacts' columns A^-1 J_i^T; the set keeps its order from round to round.
    for (Eigen::Index j = solved; j < c; ++j) {
      auto col = columns_.col(j);
      col.setZero();
      const ImpactLimiter::Contact& cj = set_[j];
      for (int side = 0; side < (cj.b >= 0 ? 2 : 1); ++side) {
        const collision::Sphere& sp = spheres[side == 0 ? cj.a : cj.b];
        const Vec3 n = side == 0 ? cj.normal : Vec3(-cj.normal);
        for (int k = 0; k < 4; ++k) col.segment<3>(3 * (sp.first + k)) += sp.w[k] * n;
      }
    }
    for (Eigen::Index j = solved; j < c; ++j) band_inverse_(columns_.col(j).data());
    solved = c;
    // The new contacts' entries G(i, j) = J_i A^-1 J_j^T, i <= j; the earlier ones are the same
    // contacts and columns as the last round's, so their entries stand.
    delassus_.Fill(set_, [&](Eigen::Index i, Eigen::Index j) {
      return ContactSpeed(set_[i], columns_.col(j).data());
    });
    for (Eigen::Index i = 0; i < c; ++i) {
      speed_(i) = set_[i].normal_speed;
      target_(i) = set_[i].target;
    }
    SolveContactImpulses(delassus_.matrix(), c, target_, immobile, &lambda_, &speed_);
    delta->noalias() = columns_.leftCols(c) * lambda_.head(c);
    check_ = base + Eigen::Map<const Points>(delta->data(), n_, 3);
    any = true;
  }
  if (!any) return false;
  contacts_total_ += static_cast<int64_t>(set_.size());
  // Between two parts of a free tube an impulse moves no momentum to the world. Against an
  // obstacle it does (and a translation would change that contact's speed); a tube held by pins,
  // attachments, its mesentery or a tool gives the world momentum through them, and a translation
  // would move it along those ties too.
  const ModelParams& p = model_.params();
  const bool free =
      model_.pins().empty() && p.attachments.empty() && !p.mesentery && p.tools.empty();
  const bool only_self = std::all_of(set_.begin(), set_.end(),
                                     [](const ImpactLimiter::Contact& c) { return c.b >= 0; });
  if (momentum_kept_ && free && only_self) KeepPairsMomentum(h, delta);
  return true;
}

void EndConstraints::KeepPairsMomentum(double h, VecX* delta) {
  // delta = A^-1 J^T Λ through the band system, which holds each self pair's coupling H as 2 H
  // on each side's own window: the exact matrix plus the pair's common mode (J_a + J_b)^T H
  // (J_a + J_b), which ties the pair's common motion to the world. Summed over the points,
  // A delta = J^T Λ gives M delta the momentum the exact matrix would (what the tube's other
  // ties to the world take: mesentery, tools, drag) less the sum of that common mode's force,
  // which no force gave: an arm hitting another at 1 kHz gained up to 1.5 times one arm's
  // momentum from it (tests/mechanics/self_impact_momentum_test.cc). That momentum is taken out
  // by a uniform velocity, which changes no pair's relative speed or gap: every constraint
  // holds as solved.
  if (interactions_->coupled_pairs() == 0) return;
  interactions_->WeighCommonModes(-h * h, -h);  // backward Euler's, as the solve weighed them
  check_.setZero();                             // free after the rounds: scratch, no allocation
  interactions_->AddCommonModeTerms(delta->data(), check_.data());
  const Vec3 drift = check_.colwise().sum().transpose() / TotalMass(model_.mass_band());
  for (int j = 0; j < n_; ++j) delta->segment<3>(3 * j) -= drift;
}

bool EndConstraints::Needed(double h, const Points& dq) {
  if (interactions_ == nullptr || !model_.params().contacts.impact_constraints) return false;
  // The constraints bound where the sub-step leaves the pairs: the speed that moves q by dq.
  check_ = dq / h;
  return interactions_->GatherEndConstraints(Interactions::EndConstraint::kImpact, h, check_,
                                             check_, true, &set_) ||
         interactions_->GatherEndConstraints(Interactions::EndConstraint::kDepth, h, check_, check_,
                                             true, &set_);
}

bool EndConstraints::Resolve(double h, const Points& v, Eigen::Ref<VecX> dv) {
  if (interactions_ == nullptr || !model_.params().contacts.impact_constraints) return false;
  // Impacts: their impulses stay in the velocity (inelastic, never a push apart).
  v_ = v + Eigen::Map<const Points>(dv.data(), n_, 3);
  const bool impacts = Solve(Interactions::EndConstraint::kImpact, h, v_, &impact_dv_);
  if (impacts) {
    dv += impact_dv_;
    v_ += Eigen::Map<const Points>(impact_dv_.data(), n_, 3);
  }
  // Depth: a position correction only (q moves by h times it, v keeps none of it), so it never
  // gives a pair a separating speed.
  const bool depth = Solve(Interactions::EndConstraint::kDepth, h, v_, &depth_dq_);
  if (impacts || depth) ++substeps_;
  return depth;
}

}  // namespace viscera::mechanics
