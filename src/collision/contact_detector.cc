#include "collision/contact_detector.h"

#include <algorithm>

namespace viscera::collision {

Vec3 ClosestOnSegment(const Vec3& port, const Vec3& tip, const Vec3& p, double* fraction) {
  const Vec3 d = tip - port;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - port).dot(d) / len2, 0.0, 1.0) : 1.0;
  *fraction = t;
  return port + t * d;
}

ContactDetector::ContactDetector(double radius, double margin, bool self_contacts, int self_skip)
    : radius_(radius), margin_(margin), self_(self_contacts), self_skip_(self_skip), grid_(2.0 * radius + margin) {}

void ContactDetector::Detect(const std::vector<Sphere>& spheres, const std::vector<Obstacle>& obstacles,
                             const std::vector<ToolCapsule>& tools, std::vector<ContactCandidate>* out,
                             double margin) {
  out->clear();
  const double extra = margin >= 0.0 ? margin : margin_;
  grid_.set_cell(2.0 * radius_ + extra);
  const int n = static_cast<int>(spheres.size());
  if (self_) {
    centres_.resize(n);
    for (int i = 0; i < n; ++i) centres_[i] = spheres[i].centre;
    const double reach = 2.0 * radius_ + extra;
    grid_.ForEachCandidatePair(centres_, [&](int i, int j) {
      if (j - i < self_skip_) return;
      if ((centres_[i] - centres_[j]).squaredNorm() < reach * reach) out->push_back({ContactKind::kSelf, i, j});
    });
  }
  for (int i = 0; i < n; ++i) {
    for (size_t o = 0; o < obstacles.size(); ++o) {
      if (SignedDistance(obstacles[o], spheres[i].centre) < radius_ + extra) {
        out->push_back({ContactKind::kEnvironment, i, static_cast<int>(o)});
      }
    }
    for (size_t t = 0; t < tools.size(); ++t) {
      if (!tools[t].present) continue;
      double fraction;
      const Vec3 p = ClosestOnSegment(tools[t].port, tools[t].tip, spheres[i].centre, &fraction);
      if ((spheres[i].centre - p).norm() < radius_ + tools[t].radius + extra) {
        out->push_back({ContactKind::kTool, i, static_cast<int>(t)});
      }
    }
  }
}

}  // namespace viscera::collision
