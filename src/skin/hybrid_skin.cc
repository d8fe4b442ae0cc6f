#include "skin/hybrid_skin.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"
#include "skin/parametric_skin.h"

namespace viscera::skin {

double FocusWeight(double distance, double focus_radius, double transition) {
  if (transition <= 0.0) return distance <= focus_radius ? 1.0 : 0.0;
  const double t = std::clamp((focus_radius + transition - distance) / transition, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

HybridSkin::HybridSkin(double radius, const ParametricOptions& parametric,
                       const ConvolutionOptions& convolution, const HybridOptions& hybrid)
    : r_min_(parametric.radius_min_factor * radius),
      r_max_(parametric.radius_max_factor * radius),
      hybrid_(hybrid),
      prevent_folds_(convolution.prevent_folds),
      convolution_(radius, convolution) {
  ThrowUnless(0.0 < r_min_ && r_min_ <= r_max_,
              "hybrid skin needs 0 < Rmin <= Rmax, got Rmin = ", r_min_, ", Rmax = ", r_max_);
  ThrowUnless(hybrid.transition >= 0.0, "hybrid transition must be >= 0, got ", hybrid.transition);
  SetFocus(hybrid.focus, hybrid.focus_radius);
}

void HybridSkin::SetFocus(const Vec3& center, double radius) {
  ThrowUnless(radius > 0.0, "focus radius must be > 0, got ", radius);
  hybrid_.focus = center;
  hybrid_.focus_radius = radius;
}

void HybridSkin::Bind(int num_control_points) { convolution_.Bind(num_control_points); }

void HybridSkin::Build(const Points& q, Mesh* out) {
  convolution_.Prepare(q);
  const TubeRays& rays = convolution_.rays();
  const int rings = rays.num_rings(), count = rays.num_vertices();
  const int segments = convolution_.curve()->num_segments();

  // ring weights: smoothstep of the ring centre's distance to the focus
  ring_weight_.resize(rings);
  active_.resize(rings);
  for (int i = 0; i < rings; ++i) {
    const double d = (rays.ring_centers()[i] - hybrid_.focus).norm();
    ring_weight_[i] = FocusWeight(d, hybrid_.focus_radius, hybrid_.transition);
    active_[i] = ring_weight_[i] > 0.0;
  }
  // parametric radius R(s) on every ray (also the start radius of new convolution seeds)
  parametric_radii_.resize(count);
  vertex_weight_.resize(count);
  for (int v = 0; v < count; ++v) {
    const int ring = rays.vertex_ring()[v];
    const double x = rays.ring_params()[ring] * segments;
    parametric_radii_[v] = ParametricRadius(r_min_, r_max_, x - std::floor(x));
    vertex_weight_[v] = ring_weight_[ring];
  }
  convolution_.Solve(&active_, &parametric_radii_, &convolution_radii_);
  radii_.resize(count);
  for (int v = 0; v < count; ++v) {
    const double w = vertex_weight_[v];
    radii_[v] = w > 0.0 ? (1.0 - w) * parametric_radii_[v] + w * convolution_radii_[v]
                        : parametric_radii_[v];
  }
  if (prevent_folds_) rays.PreventFolds(0.1, &radii_);
  rays.Emit(radii_, out);
  stats_ = convolution_.stats();
  stats_.vertices = out->num_vertices();
  stats_.triangles = out->num_triangles();
}

}  // namespace viscera::skin
