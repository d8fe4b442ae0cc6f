// A contact holds an anchor: the stretch s of a tangential spring k_t from where it stuck, and
// whether it slid in the last sub-step. With its normal force f_n (lagged: the sub-step start's):
// - stuck, it is a spring k_t and damper c in the tangent plane, linearized exactly;
// - sliding, the force is mu f_n against the way the contact moves (its stretch moved by h v_t),
//   constant over the sub-step, with no slope: the sliding force is the same at every step length.
// Once the sub-step is accepted, each anchor moves with the contact's tangential motion and is
// capped by the cone (a sliding contact drags its anchor along at mu f_n / k_t); a stuck spring
// pulled beyond the cone slides from the next sub-step on, a sliding contact that friction turned
// back sticks. Where the solve itself ends a contact far from its assumption (Revise), the
// sub-step is solved again.
#include "mechanics/stick_slip_friction.h"

#include "mechanics/avx_clone.h"

#include <algorithm>

namespace viscera::mechanics {

using collision::ContactCandidate;
using collision::ContactKind;

namespace {
// The bucket of a friction key: its kind and first sphere (StickSlipFriction::Key).
size_t AnchorBucket(uint64_t key, int spheres) {
  return static_cast<size_t>(key >> 42) * static_cast<size_t>(spheres) +
         static_cast<size_t>((key >> 21) & ((uint64_t{1} << 21) - 1));
}
}  // namespace

StickSlipFriction::StickSlipFriction(const ContactParams& cp, const collision::SphereChain& chain,
                                     double sphere_mass)
    : cp_(cp),
      chain_(chain),
      sphere_mass_(sphere_mass),
      tangential_stiffness_(cp.tangential_stiffness > 0.0 ? cp.tangential_stiffness
                                                          : kTangentialShare * cp.stiffness) {
  const size_t spheres = static_cast<size_t>(chain.size());
  pairs_.reserve(spheres * 8);
  next_anchors_.reserve(spheres * 8);
  order_.reserve(spheres * 8);
  bucket_.assign(3 * spheres + 1, 0);
  cursor_.assign(bucket_.size(), 0);
  stuck_.reserve(spheres * 8);
  slid_.reserve(spheres * 8);
  moved_.assign(spheres, Vec3::Zero());
}

void StickSlipFriction::Use(const std::vector<FrictionAnchor>* anchors, double h) {
  anchors_ = anchors;
  h_ = h;
  indexed_ = false;
  hint_ = 0;
}

void StickSlipFriction::IndexAnchors() {
  const std::vector<FrictionAnchor>* anchors = anchors_;
  indexed_ = true;
  const int spheres = chain_.size();
  std::fill(bucket_.begin(), bucket_.end(), 0);
  for (const FrictionAnchor& a : *anchors) ++bucket_[AnchorBucket(a.key, spheres) + 1];
  for (size_t i = 1; i < bucket_.size(); ++i) bucket_[i] += bucket_[i - 1];
  std::copy(bucket_.begin(), bucket_.end(), cursor_.begin());
  order_.resize(anchors->size());  // within the capacity reserved for the pairs
  for (size_t i = 0; i < anchors->size(); ++i)
    order_[cursor_[AnchorBucket((*anchors)[i].key, spheres)]++] = static_cast<int>(i);
}

const FrictionAnchor* StickSlipFriction::Find(uint64_t key) {
  const std::vector<FrictionAnchor>& anchors = *anchors_;
  if (hint_ < anchors.size() && anchors[hint_].key == key) return &anchors[hint_++];
  if (!indexed_) IndexAnchors();
  const size_t bucket = AnchorBucket(key, chain_.size());
  for (int j = bucket_[bucket]; j < bucket_[bucket + 1]; ++j) {
    const FrictionAnchor& a = anchors[order_[j]];
    if (a.key == key) {
      hint_ = static_cast<size_t>(order_[j]) + 1;
      return &a;
    }
  }
  return nullptr;
}

bool StickSlipFriction::Sticks(uint64_t key, bool held) const {
  return (held && std::find(slid_.begin(), slid_.end(), key) == slid_.end()) ||
         std::find(stuck_.begin(), stuck_.end(), key) != stuck_.end();
}

Vec3 StickSlipFriction::SlideDirection(const Vec3& stretch, const Vec3& slip) const {
  const Vec3 trial = stretch + h_ * slip;
  const double size = trial.norm();
  return size > 0.0 ? Vec3(trial / size) : Vec3(slip.normalized());
}

VISCERA_AVX_CLONE void StickSlipFriction::Add(const ContactCandidate& c, double mu,
                                              ContactPenalty* p, Mat3* k, Mat3* d) {
  const double limit = mu * std::max(p->normal_force, 0.0);
  if (!(limit > 0.0)) return;
  const Vec3& n = p->normal;
  const Mat3 tangent = Mat3::Identity() - n * n.transpose();
  const uint64_t key = Key(c.kind, c.a, c.b);
  const FrictionAnchor* found = Find(key);
  const bool anchored = found != nullptr;
  const double kt = tangential_stiffness_;
  // The anchor's spring within this sub-step's cone: an impact's damping raises f_n for a
  // sub-step, and the stretch it allowed would spring back beyond the cone once f_n fell.
  Vec3 stretch = anchored ? Vec3(tangent * found->stretch) : Vec3::Zero();
  const double size0 = kt * stretch.norm();
  if (size0 > limit) stretch *= limit / size0;
  const double ct = cp_.damping;
  const Vec3 trial = stretch + h_ * p->slip;
  // A contact sticks or slides as the last sub-step ended it (Advance), unless a stuck one's
  // trial force is already beyond kOverload times the cone (it would be solved again sliding); a
  // new one sticks if its trial force is within the cone. (The trial from the start's speed is a
  // poor guess at 100 Hz: k_t h v_t exceeds the cone at 2 mm/s, and contacts that friction stops
  // within a sub-step chattered between the two, creeping 3.7 mm/s down a 10 degree slope at
  // mu 0.3.)
  const double trial_force = (kt * trial + ct * p->slip).norm();
  const bool held =
      anchored ? !found->sliding && trial_force <= kOverload * limit : trial_force <= limit;
  const bool stuck = Sticks(key, held);
  Vec3 force, direction = Vec3::Zero();
  if (stuck) {
    // -k_t s - c v_t at the start; the solve's K and D make it -k_t (s + h v_t') - c v_t'.
    force = -kt * stretch - ct * p->slip;
    *k += kt * tangent;
    *d += ct * tangent;
  } else {
    // mu f_n against the trial stretch (the stretch moved by h v_t), held over the sub-step:
    // linearized, its turning with the motion is no longer dissipative (a slip that turned back
    // within the sub-step got work from it: the shipped fall gained 1e-8 J a step).
    direction = SlideDirection(stretch, p->slip);
    force = -limit * direction;
  }
  p->force += force;
  Pair pair;
  pair.key = key;
  pair.kind = c.kind;
  pair.a = c.a;
  pair.b = c.kind == ContactKind::kSelf ? c.b : -1;
  pair.tool = c.kind == ContactKind::kTool ? c.b : 0;
  pair.lever = p->lever;
  pair.normal = n;
  pair.stretch = stretch;
  pair.slip = p->slip;
  pair.limit = limit;
  pair.stuck = stuck;
  pair.evaluated_stuck = stuck;
  pair.held = held;
  pair.direction = direction;
  pairs_.push_back(pair);
}

VISCERA_AVX_CLONE void StickSlipFriction::GatherSpheres(const Points& x, const double* dx) {
  const auto& spheres = chain_.spheres();
  moved_.resize(spheres.size());  // the chain's count: no allocation
  for (size_t k = 0; k < spheres.size(); ++k)
    moved_[k] = ContactWindow::Of(spheres[k]).Gather(x, dx);
}

Vec3 StickSlipFriction::Motion(const Pair& pair, const Vec3& tip) const {
  Vec3 relative = moved_[pair.a];
  if (pair.kind == ContactKind::kSelf) relative -= moved_[pair.b];
  if (pair.kind == ContactKind::kTool) relative -= pair.lever.Apply(tip);
  return relative - pair.normal.dot(relative) * pair.normal;
}

VISCERA_AVX_CLONE bool StickSlipFriction::Revise(const Points& v, const double* dv,
                                                 const double* tip_dv,
                                                 const std::vector<Vec3>& tool_velocity) {
  const double kt = tangential_stiffness_;
  const double ct = cp_.damping;
  bool revised = false;
  if (!pairs_.empty()) GatherSpheres(v, dv);
  for (const Pair& pair : pairs_) {
    Vec3 tip = Vec3::Zero();
    if (pair.kind == ContactKind::kTool) {
      tip = tool_velocity[pair.tool];
      if (tip_dv != nullptr) tip += Eigen::Map<const Vec3>(tip_dv + 3 * pair.tool);
    }
    const Vec3 slip = Motion(pair, tip);
    if (pair.stuck) {
      // Held stuck, the contact pushed well beyond the cone over the sub-step (a launched loop's
      // stuck springs stopped it dead): it slides.
      const double force = (kt * (pair.stretch + h_ * slip) + ct * slip).norm();
      if (force <= kOverload * pair.limit) continue;
      // Nor where the force beyond the cone, over the sub-step, gave the pair's spheres less
      // than kOverloadSpeed.
      const double mass = pair.kind == ContactKind::kSelf ? 0.5 * sphere_mass_ : sphere_mass_;
      if (h_ * (force - pair.limit) <= kOverloadSpeed * mass) continue;
      if (std::find(slid_.begin(), slid_.end(), pair.key) != slid_.end()) continue;
      slid_.push_back(pair.key);
      revised = true;
      continue;
    }
    const double reversal = -slip.dot(pair.direction);
    if (reversal <= kReversal || kt * h_ * reversal <= kReversalShare * pair.limit) continue;
    stuck_.push_back(pair.key);
    revised = true;
  }
  return revised;
}

bool StickSlipFriction::ApplyRevisions(std::vector<Change>* changes) {
  for (const Pair& pair : pairs_) {
    if (pair.kind == ContactKind::kTool && Sticks(pair.key, pair.held) != pair.stuck) return false;
  }
  const double kt = tangential_stiffness_;
  const double ct = cp_.damping;
  changes->clear();
  for (Pair& pair : pairs_) {
    const bool stuck = Sticks(pair.key, pair.held);
    if (stuck != pair.stuck) {
      // As Add makes it: stuck, -k_t s - c v_t with its spring and damper; sliding, the cone's
      // force against the trial stretch.
      pair.stuck = stuck;
      pair.direction = stuck ? Vec3::Zero() : SlideDirection(pair.stretch, pair.slip);
    }
    if (pair.stuck == pair.evaluated_stuck) continue;
    const Vec3 held_force = -kt * pair.stretch - ct * pair.slip;
    const Vec3 sliding_force = -pair.limit * SlideDirection(pair.stretch, pair.slip);
    const Mat3 tangent = Mat3::Identity() - pair.normal * pair.normal.transpose();
    const double sign = pair.stuck ? 1.0 : -1.0;
    Change change;
    change.kind = pair.kind;
    change.a = ContactWindow::Of(chain_.spheres()[pair.a]);
    if (pair.b >= 0) change.b = ContactWindow::Of(chain_.spheres()[pair.b]);
    change.k = (sign * kt) * tangent;
    change.d = (sign * ct) * tangent;
    change.force = pair.stuck ? Vec3(held_force - sliding_force) : Vec3(sliding_force - held_force);
    changes->push_back(change);
  }
  return true;
}

VISCERA_AVX_CLONE void StickSlipFriction::Advance(const Points& dq, double h, State* state) {
  const double kt = tangential_stiffness_;
  next_anchors_.clear();
  if (!pairs_.empty()) GatherSpheres(dq, nullptr);
  for (const Pair& pair : pairs_) {
    const Vec3 tip = pair.kind == ContactKind::kTool
                         ? Vec3(h * state->tools[pair.tool].tip_velocity)
                         : Vec3::Zero();
    const Vec3 moved = Motion(pair, tip);
    Vec3 stretch = pair.stretch + moved;
    const double size = kt * stretch.norm();
    // The next sub-step starts as this one ended: a stuck spring pulled beyond the cone slides,
    // a sliding contact that friction turned back sticks.
    const bool sliding = pair.stuck ? size > pair.limit : moved.dot(pair.direction) >= 0.0;
    if (size > pair.limit) stretch *= pair.limit / size;
    next_anchors_.push_back({pair.key, stretch, sliding});
  }
  energy_ = 0.0;
  for (const FrictionAnchor& anchor : next_anchors_)
    energy_ += 0.5 * kt * anchor.stretch.squaredNorm();
  state->friction.swap(next_anchors_);
}

}  // namespace viscera::mechanics
