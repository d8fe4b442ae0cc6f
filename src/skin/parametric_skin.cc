#include "skin/parametric_skin.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/check.h"

namespace viscera::skin {

double ParametricRadius(double r_min, double r_max, double u) {
  const double c = std::cos(std::numbers::pi * u);
  return r_min + c * c * (r_max - r_min);
}

ParametricSkin::ParametricSkin(double radius, const ParametricOptions& options)
    : r_min_(options.radius_min_factor * radius),
      r_max_(options.radius_max_factor * radius),
      options_(options),
      frames_(options.frame_rule, options.frame_samples_per_segment),
      rays_(options.sides, options.cap_rings) {
  ThrowUnless(radius > 0.0, "skin radius must be > 0, got ", radius);
  ThrowUnless(0.0 < r_min_ && r_min_ <= r_max_,
              "parametric skin needs 0 < Rmin <= Rmax, got Rmin = ", r_min_, ", Rmax = ", r_max_);
  ThrowUnless(options.rings_per_segment >= 1, "rings_per_segment must be >= 1, got ",
              options.rings_per_segment);
}

void ParametricSkin::Bind(int num_control_points) {
  curve_.emplace(num_control_points);
  UniformRingParams(curve_->num_segments(), options_.rings_per_segment, &params_);
}

void ParametricSkin::RadiiFor(const TubeRays& rays, std::vector<double>* radii) const {
  VISCERA_DEMAND(curve_.has_value());
  const int n = curve_->num_segments();
  // one cos per ring, not per vertex
  const std::vector<double>& params = rays.ring_params();
  ring_radii_.resize(params.size());
  for (size_t i = 0; i < params.size(); ++i) {
    const double x = params[i] * n;
    ring_radii_[i] = ParametricRadius(r_min_, r_max_, x - std::floor(x));  // local parameter u
  }
  radii->resize(rays.num_vertices());
  for (int v = 0; v < rays.num_vertices(); ++v) (*radii)[v] = ring_radii_[rays.vertex_ring()[v]];
}

void ParametricSkin::Build(const Points& q, Mesh* out) {
  CheckSnapshot(q, curve_.has_value() ? curve_->num_points() : 0);
  frames_.Build(*curve_, q);
  rays_.Build(frames_, params_);
  RadiiFor(rays_, &radii_);
  if (options_.prevent_folds) rays_.PreventFolds(0.1, &radii_);
  rays_.Emit(radii_, out);
  stats_.vertices = out->num_vertices();
  stats_.triangles = out->num_triangles();
  stats_.rings = rays_.num_rings();
}

}  // namespace viscera::skin
