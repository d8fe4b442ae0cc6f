#include "collision/contact_detector.h"

#include <algorithm>
#include <cstdlib>

namespace viscera::collision {

Vec3 ClosestOnSegment(const Vec3& port, const Vec3& tip, const Vec3& p, double* fraction) {
  const Vec3 d = tip - port;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - port).dot(d) / len2, 0.0, 1.0) : 1.0;
  *fraction = t;
  return port + t * d;
}

ContactDetector::ContactDetector(double radius, double margin, bool self_contacts, int self_skip)
    : radius_(radius),
      margin_(margin),
      self_(self_contacts),
      self_skip_(self_skip),
      grid_(2.0 * radius + margin) {}

bool ContactDetector::NearObstacle(const Sphere& s, const Obstacle& o, double extra) const {
  return SignedDistance(o, s.centre) < radius_ + extra;
}

bool ContactDetector::NearTool(const Sphere& s, const ToolCapsule& t, double extra) const {
  if (!t.present) return false;
  double fraction;
  const Vec3 p = ClosestOnSegment(t.port, t.tip, s.centre, &fraction);
  return (s.centre - p).norm() < radius_ + t.radius + extra;
}

void ContactDetector::Detect(const std::vector<Sphere>& spheres,
                             const std::vector<Obstacle>& obstacles,
                             const std::vector<ToolCapsule>& tools,
                             std::vector<ContactCandidate>* out, double margin) {
  out->clear();
  const double extra = Extra(margin);
  grid_.set_cell(2.0 * radius_ + extra);
  const int n = static_cast<int>(spheres.size());
  if (self_) {
    centres_.resize(n);
    for (int i = 0; i < n; ++i) centres_[i] = spheres[i].centre;
    const double reach = 2.0 * radius_ + extra;
    grid_.ForEachCandidatePair(centres_, [&](int i, int j) {
      if (j - i < self_skip_) return;
      if ((centres_[i] - centres_[j]).squaredNorm() < reach * reach)
        out->push_back({ContactKind::kSelf, i, j});
    });
  }
  for (int i = 0; i < n; ++i) {
    for (size_t o = 0; o < obstacles.size(); ++o) {
      if (NearObstacle(spheres[i], obstacles[o], extra))
        out->push_back({ContactKind::kEnvironment, i, static_cast<int>(o)});
    }
    for (size_t t = 0; t < tools.size(); ++t) {
      if (NearTool(spheres[i], tools[t], extra))
        out->push_back({ContactKind::kTool, i, static_cast<int>(t)});
    }
  }
}

void ContactDetector::DetectAround(const std::vector<Sphere>& spheres,
                                   const std::vector<Obstacle>& obstacles,
                                   const std::vector<ToolCapsule>& tools,
                                   const std::vector<char>& moved_spheres,
                                   const std::vector<char>& moved_tools,
                                   std::vector<ContactCandidate>* out, double margin) {
  const double extra = Extra(margin);
  const int n = static_cast<int>(spheres.size());
  const double reach = 2.0 * radius_ + extra;
  if (self_) {
    grid_.set_cell(reach);
    centres_.resize(n);
    for (int i = 0; i < n; ++i) centres_[i] = spheres[i].centre;
    grid_.Index(centres_);
  }
  for (int i = 0; i < n; ++i) {
    if (!moved_spheres[i]) continue;
    if (self_) {
      grid_.ForEachNear(centres_[i], [&](int j) {
        // A pair of two moved spheres comes from the lower index's side only.
        if (std::abs(j - i) < self_skip_ || (moved_spheres[j] && j < i)) return;
        if ((centres_[i] - centres_[j]).squaredNorm() < reach * reach) {
          out->push_back({ContactKind::kSelf, std::min(i, j), std::max(i, j)});
        }
      });
    }
    for (size_t o = 0; o < obstacles.size(); ++o) {
      if (NearObstacle(spheres[i], obstacles[o], extra))
        out->push_back({ContactKind::kEnvironment, i, static_cast<int>(o)});
    }
    for (size_t t = 0; t < tools.size(); ++t) {
      if (NearTool(spheres[i], tools[t], extra))
        out->push_back({ContactKind::kTool, i, static_cast<int>(t)});
    }
  }
  // A moved tool against the spheres that did not move (the moved ones found it above).
  for (size_t t = 0; t < tools.size(); ++t) {
    if (!moved_tools[t]) continue;
    for (int i = 0; i < n; ++i) {
      if (!moved_spheres[i] && NearTool(spheres[i], tools[t], extra))
        out->push_back({ContactKind::kTool, i, static_cast<int>(t)});
    }
  }
}

}  // namespace viscera::collision
