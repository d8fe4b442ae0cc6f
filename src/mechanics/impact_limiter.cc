#include "mechanics/impact_limiter.h"

#include <algorithm>
#include <cmath>

#include "mechanics/contact_impulses.h"

namespace viscera::mechanics {

ImpactLimiter::ImpactLimiter(const Model& model, int spheres)
    : model_(model), mass_(model), immobile_(1e-9 / model.segment_mass()) {
  columns_.setZero(model.num_points(), 3);
  slot_of_.assign(spheres, -1);
  sphere_of_.reserve(spheres);
  pending_.reserve(spheres);
  impulse_.reserve(spheres);
  delassus_.Reserve(static_cast<size_t>(spheres) * 8);
}

int ImpactLimiter::Slot(int sphere) {
  if (slot_of_[sphere] >= 0) return slot_of_[sphere];
  const int slot = static_cast<int>(sphere_of_.size());
  slot_of_[sphere] = slot;
  sphere_of_.push_back(sphere);
  pending_.push_back(slot);
  return slot;
}

void ImpactLimiter::SolvePending(const collision::SphereChain& chain) {
  const int n = model_.num_points();
  const auto slots = static_cast<Eigen::Index>(sphere_of_.size());
  if (y_.cols() < slots) y_.conservativeResize(n, std::max<Eigen::Index>(slots, 2 * y_.cols()));
  // M acts on each axis alike, so one #N by 3 solve serves three spheres (one per column).
  for (size_t first = 0; first < pending_.size(); first += 3) {
    columns_.setZero();
    const size_t count = std::min<size_t>(3, pending_.size() - first);
    for (size_t c = 0; c < count; ++c) {
      const collision::Sphere& sp = chain.spheres()[sphere_of_[pending_[first + c]]];
      for (int k = 0; k < 4; ++k) columns_(sp.first + k, static_cast<Eigen::Index>(c)) = sp.w[k];
    }
    mass_.SolveConstrainedInPlace(&columns_);
    for (size_t c = 0; c < count; ++c)
      y_.col(pending_[first + c]) = columns_.col(static_cast<Eigen::Index>(c));
  }
  pending_.clear();
}

double ImpactLimiter::Coupling(int s, int t, const collision::SphereChain& chain) const {
  const collision::Sphere& sp = chain.spheres()[sphere_of_[s]];
  double sum = 0.0;
  for (int k = 0; k < 4; ++k) sum += sp.w[k] * y_(sp.first + k, t);
  return sum;
}

void ImpactLimiter::Reset() {
  for (int sphere : sphere_of_) slot_of_[sphere] = -1;
  sphere_of_.clear();
  pending_.clear();
  delassus_.Reset();  // the columns are solved again: so are the entries
}

double ImpactLimiter::Apply(const std::vector<Contact>& contacts,
                            const collision::SphereChain& chain, Points* u, Points* v) {
  const auto c = static_cast<Eigen::Index>(contacts.size());
  if (c == 0) return 0.0;
  for (const Contact& k : contacts) {
    Slot(k.a);
    if (k.b >= 0) Slot(k.b);
  }
  SolvePending(chain);

  // Delassus matrix G = J M^-1 J^T: a contact's normal speed per unit impulse on another. The
  // caller's set usually grows from round to round with its first contacts unchanged (and the
  // spheres' columns stand until Reset): their entries are kept, only the new ones filled in.
  delassus_.Fill(contacts, [&](Eigen::Index i, Eigen::Index j) {
    const Contact& ci = contacts[i];
    const Contact& cj = contacts[j];
    const int ai = slot_of_[ci.a], bi = ci.b >= 0 ? slot_of_[ci.b] : -1;
    const int aj = slot_of_[cj.a], bj = cj.b >= 0 ? slot_of_[cj.b] : -1;
    double g = Coupling(ai, aj, chain);
    if (bj >= 0) g -= Coupling(ai, bj, chain);
    if (bi >= 0) g -= Coupling(bi, aj, chain);
    if (bi >= 0 && bj >= 0) g += Coupling(bi, bj, chain);
    return g * ci.normal.dot(cj.normal);
  });
  if (lambda_.size() < c) {
    lambda_.resize(c);
    speed_.resize(c);
    target_.resize(c);
  }
  for (Eigen::Index i = 0; i < c; ++i) {
    speed_(i) = contacts[i].normal_speed;
    target_(i) = contacts[i].target;
  }

  // Impulses only push (λ ≥ 0), and only as much as the targets ask.
  SolveContactImpulses(delassus_.matrix(), c, target_, immobile_, &lambda_, &speed_);

  // Kinetic energy change Λ^T J v + Λ^T G Λ / 2: ≤ 0 at convergence when v is u; scaled back to
  // no gain if the iteration stopped short or v's normal speeds differ from u's.
  double lv0 = 0.0, lgl = 0.0;
  for (Eigen::Index i = 0; i < c; ++i) {
    lv0 += lambda_(i) * contacts[i].energy_speed;
    lgl += lambda_(i) * (speed_(i) - contacts[i].normal_speed);
  }
  double scale = 1.0;
  if (lgl > 0.0 && lv0 + 0.5 * lgl > 0.0) scale = std::max(0.0, -lv0 / lgl);

  // u, v += M^-1 J^T Λ: each involved sphere's impulse spread by its solved column.
  impulse_.assign(sphere_of_.size(), Vec3::Zero());
  for (Eigen::Index i = 0; i < c; ++i) {
    const Vec3 p = scale * lambda_(i) * contacts[i].normal;
    impulse_[slot_of_[contacts[i].a]] += p;
    if (contacts[i].b >= 0) impulse_[slot_of_[contacts[i].b]] -= p;
  }
  for (size_t s = 0; s < sphere_of_.size(); ++s) {
    if (impulse_[s].isZero(0.0)) continue;
    u->noalias() += y_.col(static_cast<Eigen::Index>(s)) * impulse_[s].transpose();
    if (v) v->noalias() += y_.col(static_cast<Eigen::Index>(s)) * impulse_[s].transpose();
  }
  return -(scale * lv0 + 0.5 * scale * scale * lgl);
}

}  // namespace viscera::mechanics
