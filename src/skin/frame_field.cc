#include "skin/frame_field.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"

namespace viscera::skin {
namespace {

// Unit tangent at s, falling back to the chord direction where dP/ds vanishes.
Vec3 UnitTangent(const spline::CatmullRom& curve, const Points& q, double s) {
  Vec3 t = curve.Tangent(q, s);
  double len = t.norm();
  if (len < 1e-12) {
    t = curve.Position(q, std::min(1.0, s + 1e-4)) - curve.Position(q, std::max(0.0, s - 1e-4));
    len = t.norm();
  }
  return len > 0.0 ? Vec3(t / len) : Vec3(Vec3::UnitX());
}

// Component of v perpendicular to unit t, normalized; any perpendicular if v is parallel.
Vec3 PerpendicularUnit(const Vec3& v, const Vec3& t) {
  Vec3 k = v - v.dot(t) * t;
  double len = k.norm();
  if (len < 1e-9) {
    Eigen::Index axis;
    t.cwiseAbs().minCoeff(&axis);
    k = Vec3::Unit(axis) - t[axis] * t;
    len = k.norm();
  }
  return k / len;
}

}  // namespace

Vec3 CarryNormal(FrameRule rule, const Vec3& x0, const Vec3& t0, const Vec3& k0, const Vec3& x1,
                 const Vec3& t1) {
  if (rule == FrameRule::kProjection) {
    // b_s = t_s x k_{s-ds}, k_s = b_s x t_s (France et al. 2005, sec. 4.1.1).
    const Vec3 b = t1.cross(k0);
    if (b.squaredNorm() < 1e-18) return PerpendicularUnit(k0, t1);
    return b.cross(t1).normalized();
  }
  // Double reflection (Wang et al. 2008, algorithm 1).
  const Vec3 v1 = x1 - x0;
  const double c1 = v1.squaredNorm();
  Vec3 k_l = k0, t_l = t0;
  if (c1 > 1e-24) {
    k_l = k0 - (2.0 / c1) * v1.dot(k0) * v1;
    t_l = t0 - (2.0 / c1) * v1.dot(t0) * v1;
  }
  const Vec3 v2 = t1 - t_l;
  const double c2 = v2.squaredNorm();
  const Vec3 k1 = c2 > 1e-24 ? Vec3(k_l - (2.0 / c2) * v2.dot(k_l) * v2) : k_l;
  // Re-orthonormalize against round-off drift over thousands of steps.
  return PerpendicularUnit(k1, t1);
}

FrameField::FrameField(FrameRule rule, int samples_per_segment)
    : rule_(rule), samples_per_segment_(samples_per_segment) {
  ThrowUnless(samples_per_segment >= 1, "frame samples per segment must be >= 1, got ",
              samples_per_segment);
}

void FrameField::Build(const spline::CatmullRom& curve, const Points& q) {
  VISCERA_DEMAND(q.rows() == curve.num_points());
  curve_ = &curve;
  q_ = q;
  const int count = curve.num_segments() * samples_per_segment_ + 1;
  samples_.resize(count);
  Frame& first = samples_[0];
  first.position = curve.Position(q, 0.0);
  first.tangent = UnitTangent(curve, q, 0.0);
  Vec3 seed_normal = previous_first_normal_;
  if (!has_previous_) {
    Eigen::Index axis;
    first.tangent.cwiseAbs().minCoeff(&axis);
    seed_normal = Vec3::Unit(axis);
  }
  first.normal = PerpendicularUnit(seed_normal, first.tangent);
  first.binormal = first.tangent.cross(first.normal);
  for (int i = 1; i < count; ++i) {
    samples_[i] = Propagate(samples_[i - 1], static_cast<double>(i) / (count - 1));
  }
  previous_first_normal_ = first.normal;
  has_previous_ = true;
}

Frame FrameField::Propagate(const Frame& from, double s) const {
  Frame f;
  f.position = curve_->Position(q_, s);
  f.tangent = UnitTangent(*curve_, q_, s);
  f.normal = CarryNormal(rule_, from.position, from.tangent, from.normal, f.position, f.tangent);
  f.binormal = f.tangent.cross(f.normal);
  return f;
}

Frame FrameField::At(double s) const {
  VISCERA_ASSERT(!samples_.empty());
  s = std::clamp(s, 0.0, 1.0);
  const int last = static_cast<int>(samples_.size()) - 1;
  const double x = s * last;
  const int i = std::min(static_cast<int>(x), last);
  if (x - i < 1e-12) return samples_[i];
  return Propagate(samples_[i], s);
}

}  // namespace viscera::skin
