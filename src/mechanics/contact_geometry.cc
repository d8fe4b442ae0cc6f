#include "mechanics/contact_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace viscera::mechanics {

using collision::ContactCandidate;
using collision::ContactKind;

ContactGeometry::ContactGeometry(const Model& model, const collision::SphereChain& chain,
                                 const collision::VerletList& candidates, const Grasps& grasps)
    : model_(model),
      chain_(chain),
      candidates_(candidates),
      grasps_(grasps),
      radius_(model.params().radius) {
  obstacles_.reserve(model.params().obstacles.size());
  for (const collision::Obstacle& o : model.params().obstacles) obstacles_.emplace_back(o);
  capsules_.resize(model.params().tools.size());
}

void ContactGeometry::Ensure() {
  if (valid_) return;
  const auto& list = candidates_.candidates();
  penalties_.resize(list.size());  // grows with the list's high-water mark only
  // Most candidates are self pairs (the Verlet list's skin holds far more than touch): they go
  // four at a time (SelfBatch), the others one by one.
  std::array<int, 4> batch;
  int batched = 0;
  for (size_t i = 0; i < list.size(); ++i) {
    if (list[i].kind != ContactKind::kSelf) {
      penalties_[i] = Of(list[i]);
      continue;
    }
    batch[batched++] = static_cast<int>(i);
    if (batched == 4) {
      SelfBatch(batch, batched);
      batched = 0;
    }
  }
  if (batched > 0) SelfBatch(batch, batched);
  // In a local: a member would be stored and loaded again at every candidate (the compiler
  // cannot tell it from the geometry's doubles), a chain through memory as long as the list.
  double deepest = -std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < list.size(); ++i) {
    // NaN (a blown-up step) counts as deepest: nothing is skipped on it.
    const double depth = std::isnan(penalties_[i].depth) ? std::numeric_limits<double>::infinity()
                                                         : penalties_[i].depth;
    if (list[i].kind != ContactKind::kTool) deepest = std::max(deepest, depth);
  }
  deepest_ = deepest;
  valid_ = true;
}

void ContactGeometry::SelfBatch(const std::array<int, 4>& batch, int count) {
  const auto& list = candidates_.candidates();
  const auto& spheres = chain_.spheres();
  std::array<const Vec3*, 4> a, b;
  for (int l = 0; l < count; ++l) {
    a[l] = &spheres[list[batch[l]].a].centre;
    b[l] = &spheres[list[batch[l]].b].centre;
  }
  std::array<collision::PairSeparation, 4> separation;
  collision::Separations(a, b, count, separation.data());
  for (int l = 0; l < count; ++l) penalties_[batch[l]] = SelfPenalty(separation[l]);
}

PairGeometry ContactGeometry::SelfPenalty(const collision::PairSeparation& separation) const {
  PairGeometry p;
  p.normal = separation.normal;
  p.clearance = separation.distance - 2.0 * radius_;
  p.depth = -p.clearance;
  return p;
}

void ContactGeometry::RefreshTools() {
  if (!valid_) return;
  const auto& list = candidates_.candidates();
  for (size_t i = 0; i < list.size(); ++i) {
    if (list[i].kind == ContactKind::kTool) penalties_[i] = Of(list[i]);
  }
}

PairGeometry ContactGeometry::Of(const ContactCandidate& c) const {
  if (!grasps_.Held(c)) return Raw(c);
  PairGeometry p;
  p.clearance = 1.0;  // m: never a contact, never within any margin
  p.depth = -p.clearance;
  return p;
}

PairGeometry ContactGeometry::Raw(const ContactCandidate& c) const {
  const collision::Sphere& sa = chain_.spheres()[c.a];
  PairGeometry p;
  double reach = radius_;
  double distance = 0.0;
  switch (c.kind) {
    case ContactKind::kSelf:  // (Ensure does these four at a time: SelfBatch)
      return SelfPenalty(collision::Separation(sa.centre, chain_.spheres()[c.b].centre));
    case ContactKind::kEnvironment:
      distance = obstacles_[c.b].SignedDistance(sa.centre, &p.normal);
      break;
    case ContactKind::kTool: {
      const collision::ToolCapsule& cap = capsules_[c.b];
      const Vec3 on_shaft =
          collision::ClosestOnSegment(cap.port, cap.tip, sa.centre, &p.lever.fraction);
      const Vec3 shaft = cap.tip - cap.port;
      if (shaft.norm() > 1e-12) p.lever.axis = shaft.normalized();
      const Vec3 d = sa.centre - on_shaft;
      distance = d.norm();
      p.normal = distance > 1e-12 ? Vec3(d * (1.0 / distance)) : Vec3::UnitZ();
      reach = radius_ + cap.radius;
      break;
    }
  }
  p.clearance = distance - reach;
  p.depth = -p.clearance;
  return p;
}

}  // namespace viscera::mechanics
