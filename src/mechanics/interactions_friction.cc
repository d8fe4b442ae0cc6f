// Coulomb friction with a static phase for the implicit step (docs/contacts.md, "Friction"). A
// contact holds an anchor: the stretch s of a tangential spring k_t from where it stuck. At a
// sub-step's start, with its normal force f_n (lagged: the start's), the trial force of the
// spring moved by the tangential motion h v_t is -k_t (s + h v_t) - c v_t:
// - within the cone (|trial| <= mu f_n) the contact sticks: a spring k_t and damper c in the
//   tangent plane, linearized exactly, so a loop on a slope below atan mu holds still;
// - outside, it slides: the force is mu f_n against the trial stretch's direction, constant in
//   size, its only stiffness the turning of that direction (mu f_n / |trial| sideways). No
//   viscous slope: the sliding force is the same at every step length.
// Once the sub-step is accepted, each anchor moves with the contact's tangential motion and is
// capped by the cone (a sliding contact drags its anchor along at mu f_n / k_t).
#include <algorithm>

#include "mechanics/interactions.h"

namespace viscera::mechanics {

using collision::ContactCandidate;
using collision::ContactKind;

double Interactions::Friction(ContactKind kind) const {
  const ContactParams& cp = model_.params().contacts;
  switch (kind) {
    case ContactKind::kSelf: return cp.self_friction;
    case ContactKind::kTool: return cp.tool_friction;
    case ContactKind::kEnvironment: break;
  }
  return cp.friction;
}

void Interactions::AddStickSlip(const ContactCandidate& c, int candidate, Penalty* p, Mat3* k, Mat3* d) {
  const double limit = Friction(c.kind) * std::max(p->normal_force, 0.0);
  if (!(limit > 0.0)) return;
  const Vec3& n = p->normal;
  const Mat3 tangent = Mat3::Identity() - n * n.transpose();
  const uint64_t key = FrictionKey(c.kind, c.a, c.b);
  Vec3 stretch = Vec3::Zero();
  const auto found = std::lower_bound(anchors_->begin(), anchors_->end(), key,
                                      [](const FrictionAnchor& a, uint64_t k) { return a.key < k; });
  if (found != anchors_->end() && found->key == key) stretch = tangent * found->stretch;
  const double kt = tangential_stiffness_;
  const double ct = model_.params().contacts.damping;
  const Vec3 trial = stretch + friction_h_ * p->slip;
  bool stuck = (kt * trial + ct * p->slip).norm() <= limit;
  for (const auto& [revised, stick] : friction_revised_) {
    if (revised == candidate) stuck = stick;
  }
  Vec3 force, direction = Vec3::Zero();
  if (stuck) {
    // -k_t s - c v_t at the start; the solve's K and D make it -k_t (s + h v_t') - c v_t'.
    force = -kt * stretch - ct * p->slip;
    *k += kt * tangent;
    *d += ct * tangent;
  } else {
    // mu f_n against the trial stretch, which h v_t already moved; the solve's K turns it with
    // the rest of the motion, h (v_t' - v_t), so the start's force is the trial's plus K h v_t.
    const double size = trial.norm();
    direction = size > 0.0 ? Vec3(trial / size) : Vec3(p->slip.normalized());
    force = -limit * direction;
    if (size > 0.0) {
      const Mat3 sideways = (limit / size) * (tangent - direction * direction.transpose());
      force += sideways * (friction_h_ * p->slip);
      *k += sideways;
    }
  }
  p->force += force;
  const collision::Sphere& sa = chain_.spheres()[c.a];
  FrictionPair pair;
  pair.key = key;
  pair.kind = c.kind;
  pair.first_a = sa.first;
  pair.w_a = sa.w;
  if (c.kind == ContactKind::kSelf) {
    const collision::Sphere& sb = chain_.spheres()[c.b];
    pair.first_b = sb.first;
    pair.w_b = sb.w;
  }
  pair.tool = c.kind == ContactKind::kTool ? c.b : 0;
  pair.lever = p->lever;
  pair.normal = n;
  pair.stretch = stretch;
  pair.limit = limit;
  pair.candidate = candidate;
  pair.stuck = stuck;
  pair.direction = direction;
  friction_pairs_.push_back(pair);
}

bool Interactions::ReviseFriction(const Points& v, const double* dv, const double* tip_dv) {
  auto window = [&](int first, const std::array<double, 4>& w) {
    Vec3 m = Vec3::Zero();
    for (int i = 0; i < 4; ++i) m += w[i] * (v.row(first + i).transpose() + Eigen::Map<const Vec3>(dv + 3 * (first + i)));
    return m;
  };
  const double kt = tangential_stiffness_;
  const double ct = model_.params().contacts.damping;
  bool revised = false;
  for (const FrictionPair& pair : friction_pairs_) {
    Vec3 relative = window(pair.first_a, pair.w_a);
    if (pair.kind == ContactKind::kSelf) relative -= window(pair.first_b, pair.w_b);
    if (pair.kind == ContactKind::kTool) {
      Vec3 tip = tool_velocity_[pair.tool];
      if (tip_dv != nullptr) tip += Eigen::Map<const Vec3>(tip_dv + 3 * pair.tool);
      relative -= pair.lever * tip;
    }
    const Vec3 slip = relative - pair.normal.dot(relative) * pair.normal;
    bool stuck = pair.stuck;
    if (pair.stuck) {
      // Stuck, the spring ends beyond the cone (a little beyond: rounding is no reason to solve again).
      stuck = (kt * (pair.stretch + friction_h_ * slip) + ct * slip).norm() <= 1.001 * pair.limit;
    } else {
      // Sliding, the friction turned the motion back: the contact stopped within the sub-step.
      stuck = slip.dot(pair.direction) < 0.0;
    }
    if (stuck == pair.stuck) continue;
    // A contact revised before keeps that choice, unless made to stick and still beyond the
    // cone: then it slides (no flip-flop between two solves).
    auto known = std::find_if(friction_revised_.begin(), friction_revised_.end(),
                              [&pair](const std::pair<int, bool>& r) { return r.first == pair.candidate; });
    if (known == friction_revised_.end()) {
      friction_revised_.push_back({pair.candidate, stuck});
      revised = true;
    } else if (known->second && !stuck) {
      known->second = false;
      revised = true;
    }
  }
  return revised;
}

void Interactions::AdvanceFriction(const Points& dq, double h, State* state) {
  auto moved = [&dq](int first, const std::array<double, 4>& w) {
    Vec3 m = Vec3::Zero();
    for (int i = 0; i < 4; ++i) m += w[i] * dq.row(first + i).transpose();
    return m;
  };
  const double kt = tangential_stiffness_;
  next_anchors_.clear();
  for (const FrictionPair& pair : friction_pairs_) {
    Vec3 relative = moved(pair.first_a, pair.w_a);
    if (pair.kind == ContactKind::kSelf) relative -= moved(pair.first_b, pair.w_b);
    if (pair.kind == ContactKind::kTool) relative -= pair.lever * h * state->tools[pair.tool].tip_velocity;
    Vec3 stretch = pair.stretch + relative - pair.normal.dot(relative) * pair.normal;
    const double size = kt * stretch.norm();
    if (size > pair.limit) stretch *= pair.limit / size;
    next_anchors_.push_back({pair.key, stretch});
  }
  std::sort(next_anchors_.begin(), next_anchors_.end(),
            [](const FrictionAnchor& a, const FrictionAnchor& b) { return a.key < b.key; });
  state->friction.swap(next_anchors_);
}

}  // namespace viscera::mechanics
