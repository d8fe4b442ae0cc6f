#include "mechanics/impact_sets.h"

#include "mechanics/avx_clone.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mechanics/contact_law.h"

namespace viscera::mechanics {

using collision::ContactCandidate;
using collision::ContactKind;

namespace {

// Impacts are closing faster than the linear law stops within 2 x impact_depth (a sphere's own
// mass against k; 0.5 m/s with the defaults). Slower pairs (a tool pressing loops together, a
// pile settling) are the penalty's: with half that, the clearing gesture's 1 kHz reference
// carried its loop with 1 % less force, so impulses were absorbing what the hand should feel.
double ImpactSpeed(const ContactParams& cp, double radius, double sphere_mass) {
  const double allowed = cp.impact_depth * radius;
  return 2.0 * allowed * std::sqrt(cp.stiffness / sphere_mass);
}

}  // namespace

ImpactSets::ImpactSets(const Model& model, const collision::SphereChain& chain,
                       const collision::VerletList& candidates, ContactGeometry* geometry,
                       double sphere_mass)
    : model_(model),
      chain_(chain),
      candidates_(candidates),
      geometry_(*geometry),
      radius_(model.params().radius),
      impact_speed_(ImpactSpeed(model.params().contacts, radius_, sphere_mass)),
      limiter_(model, chain.size()) {
  velocity_.assign(chain.size(), Vec3::Zero());
  end_velocity_.assign(chain.size(), Vec3::Zero());
  contacts_.reserve(static_cast<size_t>(chain.size()) * 8);
}

VISCERA_AVX_CLONE double ImpactSets::GatherSpheres(const Points& v, std::vector<Vec3>* out) const {
  double fastest = 0.0;
  for (int k = 0; k < chain_.size(); ++k) {
    (*out)[k] = SphereVelocity(k, v);
    fastest = std::max(fastest, (*out)[k].squaredNorm());
  }
  return std::sqrt(fastest);
}

VISCERA_AVX_CLONE bool ImpactSets::Limit(double h, Points* u, Points* v, double u_fastest) {
  const double allowed = model_.params().contacts.impact_depth * radius_;
  set_.clear();
  if (!(allowed > 0.0)) return false;
  geometry_.Ensure();
  const auto& list = candidates_.candidates();
  // The set of contacts grows until the impulses on it leave no other contact too fast: an
  // impulse can drive a sphere into a contact that was not closing before. Each round solves
  // the whole set again from the velocities before any impulse, so the result is the set's
  // exact (dissipative) solution.
  constexpr int kMaxRounds = 8;
  in_set_.assign(list.size(), 0);  // grows with the list's high-water mark only
  limiter_.Reset();
  auto other = [&](const ContactCandidate& c) {
    return c.kind == ContactKind::kSelf ? velocity_[c.b] : Vec3::Zero();
  };
  for (int round = 0; round < kMaxRounds; ++round) {
    // No pair closes as fast as an impact: no impulse, as in most steps of a settled pile,
    // without looking at each pair.
    const double slowest_impact = impact_speed_ * (1.0 - 1e-6);
    if (round == 0 && u_fastest >= 0.0 && 2.0 * u_fastest < slowest_impact) return false;
    const double fastest = GatherSpheres(*u, &velocity_);
    if (round == 0 && 2.0 * fastest < slowest_impact) return false;
    bool grew = false;
    for (size_t i = 0; i < list.size(); ++i) {
      if (in_set_[i] || list[i].kind == ContactKind::kTool) continue;
      const PairGeometry& p = geometry_[i];
      const double un = (velocity_[list[i].a] - other(list[i])).dot(p.normal);
      // The end depth, depth - h u_n, must not exceed `allowed`; never asks a pair to separate.
      // Slower pairs are the penalty's (the law stops them within `allowed`): a tool pressing
      // loops together is felt through the contacts' springs, not absorbed by impulses.
      if (un >= std::min(0.0, (p.depth - allowed) / h) - 1e-9 || -un < impact_speed_) continue;
      in_set_[i] = 1;
      set_.push_back(static_cast<int>(i));
      grew = true;
    }
    if (!grew) break;
    if (round == 0) {
      u0_ = *u;  // same size after the first: no allocation
      if (v) v0_ = *v;
    } else {
      *u = u0_;
      if (v) *v = v0_;
      GatherSpheres(*u, &velocity_);
    }
    contacts_.clear();
    for (int i : set_) {
      const ContactCandidate& c = list[i];
      const PairGeometry& p = geometry_[i];
      const double un = (velocity_[c.a] - other(c)).dot(p.normal);
      // The velocity whose kinetic energy counts (the step's end), when it is not u itself.
      double vn = un;
      if (v) {
        const Vec3 vb = c.kind == ContactKind::kSelf ? SphereVelocity(c.b, *v) : other(c);
        vn = (SphereVelocity(c.a, *v) - vb).dot(p.normal);
      }
      contacts_.push_back({c.a, c.kind == ContactKind::kSelf ? c.b : -1, p.normal, un,
                           std::min(0.0, (p.depth - allowed) / h), vn});
    }
    limiter_.Apply(contacts_, chain_, u, v);
  }
  return !set_.empty();
}

VISCERA_AVX_CLONE bool ImpactSets::GatherEnd(EndConstraint kind, double h, const Points& v_check,
                                             const Points& v_base, bool first,
                                             std::vector<ImpactLimiter::Contact>* contacts) {
  const ContactParams& cp = model_.params().contacts;
  const bool impact = kind == EndConstraint::kImpact;
  if (!(cp.impact_depth > 0.0) || !cp.impact_constraints ||
      (!impact && cp.impact_depth >= ContactLaw::kDepthGoal))
    return false;
  // The depth bound sits a quarter of the way from impact_depth to the goal: the linearized end
  // depth misses up to ~3.5 % of R (pairs that appear or turn within the sub-step), and a pile
  // held where the law is 25 k stiff, not 50 k (half-way), gains no energy from its single
  // linearization per sub-step (docs/impacts.md).
  const double allowed =
      (impact ? cp.impact_depth
              : cp.impact_depth + 0.25 * (ContactLaw::kDepthGoal - cp.impact_depth)) *
      radius_;
  const double impact_speed = impact ? impact_speed_ : 0.0;
  // The least normal speed that ends the sub-step within `allowed`; impacts are never pushed apart.
  auto target = [&](const PairGeometry& p) {
    return impact ? std::min(0.0, (p.depth - allowed) / h) : (p.depth - allowed) / h;
  };
  geometry_.Ensure();  // the sub-step's start, as the forces saw it
  const auto& list = candidates_.candidates();
  if (first) {
    end_set_.clear();
    in_end_set_.assign(list.size(), 0);  // grows with the list's high-water mark only
  }
  // The scan reads v_check's sphere velocities once per sphere, not once per pair and side: the
  // same numbers (SphereVelocity of the same rows), a fraction of the work.
  // They stand while v_check and the chain are the last scan's (the depth scan after an impact
  // scan that added no impulse reads the same velocities).
  const bool same = end_gathered_ && v_check.rows() == end_checked_.rows() &&
                    (v_check.array() == end_checked_.array()).all();
  if (!same) {
    double fastest = 0.0;
    bool finite = true;
    for (int k = 0; k < chain_.size(); ++k) {
      end_velocity_[k] = SphereVelocity(k, v_check);
      const double speed2 = end_velocity_[k].squaredNorm();
      fastest = std::max(fastest, speed2);
      finite = finite && std::isfinite(speed2);
    }
    end_fastest_ = fastest;
    end_finite_ = finite;
    end_checked_ = v_check;  // same size after the first: no allocation
    end_gathered_ = true;
  }
  const bool finite = end_finite_;
  // Shortcuts that skip only pairs the test below would skip, from |u_n| <= |v_a| + |v_b|
  // <= `closing` (not with non-finite velocities, which the test lets in).
  const double closing = 2.0 * std::sqrt(end_fastest_);
  // No pair closes as fast as an impact: none would join, as in most sub-steps of a settled
  // pile, without looking at each pair.
  if (finite && impact && closing < impact_speed * (1.0 - 1e-6)) return false;
  // A pair no deeper than this cannot end the sub-step beyond `allowed` at any closing speed up
  // to `closing`: its target is below -closing by far more than the rounding (relative 1e-3,
  // and 1e-12 m), so u_n >= target - 1e-9. Most pairs of a pile, and often all of them.
  const double shallow = finite ? allowed - h * closing * (1.0 + 1e-3) - 1e-12
                                : -std::numeric_limits<double>::infinity();
  if (geometry_.deepest() <= shallow) return false;
  bool grew = false;
  for (size_t i = 0; i < list.size(); ++i) {
    if (in_end_set_[i] || list[i].kind == ContactKind::kTool) continue;
    const ContactCandidate& c = list[i];
    const PairGeometry& p = geometry_[i];
    if (p.depth <= shallow) continue;
    const Vec3 other = c.kind == ContactKind::kSelf ? end_velocity_[c.b] : Vec3::Zero();
    const double un = (end_velocity_[c.a] - other).dot(p.normal);
    if (un >= target(p) - 1e-9 || -un < impact_speed) continue;
    in_end_set_[i] = 1;
    end_set_.push_back(static_cast<int>(i));
    grew = true;
  }
  if (!grew) return false;
  contacts->clear();
  for (int i : end_set_) {
    const ContactCandidate& c = list[i];
    const PairGeometry& p = geometry_[i];
    const Vec3 other = c.kind == ContactKind::kSelf ? SphereVelocity(c.b, v_base) : Vec3::Zero();
    const double un = (SphereVelocity(c.a, v_base) - other).dot(p.normal);
    contacts->push_back(
        {c.a, c.kind == ContactKind::kSelf ? c.b : -1, p.normal, un, target(p), un});
  }
  return true;
}

}  // namespace viscera::mechanics
