#include "assessment/exposure.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "assessment/target_samples.h"
#include "common/check.h"

namespace viscera::assessment {

double SegmentSegmentDistanceSquared(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                     const Vec3& q1) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  constexpr double kTiny = 1e-18;
  double s = 0.0, t = 0.0;
  if (a <= kTiny && e <= kTiny) return r.squaredNorm();
  if (a <= kTiny) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= kTiny) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > kTiny ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return (p0 + s * d1 - (q0 + t * d2)).squaredNorm();
}

ExposureEvaluator::ExposureEvaluator(const std::vector<mechanics::TargetParams>& targets,
                                     double tube_radius)
    : targets_(targets), radius_(tube_radius) {
  VISCERA_DEMAND(tube_radius > 0.0);
  for (const mechanics::TargetParams& t : targets_) {
    samples_.push_back(TargetSamples(t));
    double extent = 0.0;
    for (const Vec3& p : samples_.back()) extent = std::max(extent, (p - t.centre).norm());
    extent_.push_back(extent);
  }
}

TargetExposure ExposureEvaluator::Evaluate(int index, const View& view,
                                           const std::vector<Vec3>& centres) const {
  const mechanics::TargetParams& target = targets_[static_cast<size_t>(index)];
  const std::vector<Vec3>& samples = samples_[static_cast<size_t>(index)];
  TargetExposure out;
  out.seen.assign(samples.size(), false);

  // camera frame: forward, right, true up; half-angle tangents of the frame
  const Vec3 axis = view.look_at - view.eye;
  const Vec3 side = axis.cross(view.up);
  // a degenerate camera (the renderer refuses it too) has no image: nothing is seen
  if (!(axis.norm() > 1e-12 && side.norm() > 1e-12 * axis.norm() * view.up.norm())) return out;
  const Vec3 forward = axis.normalized();
  const Vec3 right = side.normalized();
  const Vec3 up = right.cross(forward);
  const double tan_y = std::tan(0.5 * view.fov_y_deg * std::numbers::pi / 180.0);
  const double tan_x = tan_y * view.aspect;

  // Cone cull: every ray runs from the eye to within extent of the centre, so a capsule
  // farther than extent + radius + its half length from the segment eye-centre misses all.
  std::vector<int> near;  // index of each capsule's first centre
  for (int k = 0; k + 1 < static_cast<int>(centres.size()); ++k) {
    const Vec3 mid = 0.5 * (centres[k] + centres[k + 1]);
    const double reach =
        extent_[static_cast<size_t>(index)] + radius_ + 0.5 * (centres[k + 1] - centres[k]).norm();
    if (SegmentSegmentDistanceSquared(view.eye, target.centre, mid, mid) <= reach * reach)
      near.push_back(k);
  }
  out.capsules_tested = static_cast<int>(near.size());

  int seen = 0;
  const double r2 = radius_ * radius_;
  for (size_t i = 0; i < samples.size(); ++i) {
    const Vec3& p = samples[i];
    const Vec3 d = p - view.eye;
    if (target.normal.dot(-d) <= 0.0) continue;  // seen from behind
    const double z = d.dot(forward);
    if (z <= 0.0 || std::abs(d.dot(right)) > tan_x * z || std::abs(d.dot(up)) > tan_y * z) continue;
    bool blocked = false;
    for (const int k : near) {
      if (SegmentSegmentDistanceSquared(view.eye, p, centres[static_cast<size_t>(k)],
                                        centres[static_cast<size_t>(k) + 1]) < r2) {
        blocked = true;
        break;
      }
    }
    if (!blocked) {
      out.seen[i] = true;
      ++seen;
    }
  }
  out.fraction =
      samples.empty() ? 0.0 : static_cast<double>(seen) / static_cast<double>(samples.size());
  return out;
}

}  // namespace viscera::assessment
