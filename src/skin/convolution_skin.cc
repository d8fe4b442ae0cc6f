#include "skin/convolution_skin.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/check.h"

namespace viscera::skin {
namespace {

constexpr double kColdStartFactor = 0.05;  // cold seeds start this close to the skeleton
constexpr double kMinRadiusFactor = 0.02;  // seeds stay within [0.02 R, 4 R] of their origin
constexpr double kMaxRadiusFactor = 4.0;

}  // namespace

ConvolutionSkin::ConvolutionSkin(double radius, const ConvolutionOptions& options)
    : radius_(radius),
      options_(options),
      neighbourhood_(options.neighbourhood_factor * radius),
      frames_(options.frame_rule, options.frame_samples_per_segment),
      rays_(options.sides, options.cap_rings) {
  ThrowUnless(radius > 0.0, "skin radius must be > 0, got ", radius);
  ThrowUnless(options.neighbourhood_factor > 0.0 && options.neighbourhood_factor < 2.0,
              "local convolution needs 0 < D < 2R (France et al. 2005, sec. 4.3.1); got D = ",
              options.neighbourhood_factor, " R");
  ThrowUnless(options.skeleton_segments_per_span >= 1, "skeleton_segments_per_span must be >= 1, got ",
              options.skeleton_segments_per_span);
  ThrowUnless(options.tolerance > 0.0 && options.max_iterations >= 1,
              "convolution needs tolerance > 0 and max_iterations >= 1; got ", options.tolerance,
              ", ", options.max_iterations);
  ThrowUnless(options.max_edge_factor >= 0.0, "max_edge_factor must be >= 0, got ",
              options.max_edge_factor);
}

void ConvolutionSkin::Bind(int num_control_points) {
  curve_.emplace(num_control_points);
  has_previous_ = false;
}

void ConvolutionSkin::BuildSkeleton(const Points& q) {
  const int count = curve_->num_segments() * options_.skeleton_segments_per_span + 1;
  skeleton_.resize(count);
  skeleton_arc_.resize(count);
  for (int i = 0; i < count; ++i) {
    skeleton_[i] = curve_->Position(q, static_cast<double>(i) / (count - 1));
    skeleton_arc_[i] = i == 0 ? 0.0 : skeleton_arc_[i - 1] + (skeleton_[i] - skeleton_[i - 1]).norm();
  }
}

void ConvolutionSkin::Prepare(const Points& q) {
  ThrowUnless(curve_.has_value(), "ConvolutionSkin used before Bind");
  ThrowUnless(q.rows() == curve_->num_points(), "skin bound to ", curve_->num_points(),
              " control points, got ", q.rows());
  frames_.Build(*curve_, q);
  const double max_edge = options_.max_edge_factor > 0.0
                              ? options_.max_edge_factor * radius_
                              : 2.0 * std::numbers::pi * radius_ / options_.sides;
  AdaptiveRingParams(*curve_, q, radius_, max_edge, options_.max_angle, options_.max_depth, &params_);
  rays_.Build(frames_, params_);
  BuildSkeleton(q);
}

void ConvolutionSkin::PrepareWindows(const std::vector<char>* active) {
  const int rings = rays_.num_rings();
  const int last = static_cast<int>(skeleton_.size()) - 1;
  const double total = skeleton_arc_.back();
  windows_.resize(rings);
  iso_.resize(rings);
  log_iso_.resize(rings);
  for (int i = 0; i < rings; ++i) {
    if (active != nullptr && !(*active)[i]) continue;
    // arc length of the attachment point on the polyline skeleton
    const double x = params_[i] * last;
    const int k = std::min(static_cast<int>(x), last - 1);
    const double a = skeleton_arc_[k] + (x - k) * (skeleton_arc_[k + 1] - skeleton_arc_[k]);
    const double lo = options_.local ? std::max(0.0, a - 0.5 * neighbourhood_) : 0.0;
    const double hi = options_.local ? std::min(total, a + 0.5 * neighbourhood_) : total;
    // segments [k0, k1) overlapping (lo, hi); the first and last are clipped
    Window& w = windows_[i];
    w.k0 = static_cast<int>(std::upper_bound(skeleton_arc_.begin(), skeleton_arc_.end(), lo) -
                            skeleton_arc_.begin()) - 1;
    w.k0 = std::clamp(w.k0, 0, last - 1);
    w.k1 = static_cast<int>(std::lower_bound(skeleton_arc_.begin(), skeleton_arc_.end(), hi) -
                            skeleton_arc_.begin());
    w.k1 = std::clamp(w.k1, w.k0 + 1, last);
    auto clipped = [&](int seg) {
      const double a0 = std::max(lo, skeleton_arc_[seg]), a1 = std::min(hi, skeleton_arc_[seg + 1]);
      const double len = skeleton_arc_[seg + 1] - skeleton_arc_[seg];
      KernelSegment s;
      const Vec3 d = skeleton_[seg + 1] - skeleton_[seg];
      s.direction = len > 0.0 ? Vec3(d / len) : Vec3(Vec3::UnitX());
      s.start = skeleton_[seg] + (a0 - skeleton_arc_[seg]) * s.direction;
      s.length = std::max(0.0, a1 - a0);
      return s;
    };
    w.first = clipped(w.k0);
    w.last = clipped(w.k1 - 1);
    iso_[i] = StraightIsoValue(radius_, lo - a, hi - a);
    log_iso_[i] = std::log(iso_[i]);
  }
  // unclipped interior segments, shared by all windows
  segments_.resize(last);
  for (int k = 0; k < last; ++k) {
    const double len = skeleton_arc_[k + 1] - skeleton_arc_[k];
    segments_[k].start = skeleton_[k];
    segments_[k].direction = len > 0.0 ? Vec3((skeleton_[k + 1] - skeleton_[k]) / len) : Vec3(Vec3::UnitX());
    segments_[k].length = len;
  }
}

double ConvolutionSkin::Field(int ring, const Vec3& p) const {
  const Window& w = windows_[ring];
  const double min_d2 = 1e-6 * radius_ * radius_;
  double f = SegmentField(w.first, p, min_d2);
  if (w.k1 - w.k0 == 1) return f;
  for (int k = w.k0 + 1; k < w.k1 - 1; ++k) f += SegmentField(segments_[k], p, min_d2);
  return f + SegmentField(w.last, p, min_d2);
}

double ConvolutionSkin::SolveSeed(int ring, const Vec3& origin, const Vec3& dir, double r0,
                                  double slope, int* evaluations) const {
  // Secant iteration on y(x) = log f(origin + e^x dir) - log iso, x = log r: y is nearly
  // linear in x (slope -2 for a long straight skeleton), so one step from a warm start
  // usually lands within tolerance.
  const double x_min = std::log(kMinRadiusFactor * radius_);
  const double x_max = std::log(kMaxRadiusFactor * radius_);
  const double tol = options_.tolerance * radius_;
  auto residual = [&](double x) {
    ++*evaluations;
    return std::log(std::max(Field(ring, origin + std::exp(x) * dir), 1e-300)) - log_iso_[ring];
  };
  double x = std::clamp(std::log(r0), x_min, x_max);
  double y = residual(x);
  for (;;) {
    const double x_new = std::clamp(x - y / slope, x_min, x_max);
    const double r = std::exp(x), r_new = std::exp(x_new);
    if (std::abs(r_new - r) < tol || *evaluations >= options_.max_iterations) return r_new;
    const double y_new = residual(x_new);
    const double secant = (y_new - y) / (x_new - x);
    // keep the last slope if the secant is not a usable (decreasing) one
    if (std::isfinite(secant) && secant < -0.25) slope = secant;
    x = x_new;
    y = y_new;
  }
}

void ConvolutionSkin::WarmStartGuesses() {
  const int count = rays_.num_vertices();
  start_radii_.assign(count, 0.0);
  start_valid_.assign(count, 0);
  if (!has_previous_ || !options_.warm_start) return;
  const int m = rays_.sides();
  const int first_tube = rays_.FirstTubeVertex();
  const int rings = rays_.num_rings();
  const int prev_rings = static_cast<int>(previous_params_.size());
  const int prev_count = static_cast<int>(previous_radii_.size());
  // caps keep their layout: same offsets from the start / the end of the vertex array
  for (int v = 0; v < first_tube; ++v) {
    start_radii_[v] = previous_radii_[v];
    start_valid_[v] = previous_valid_[0];
  }
  const int back_cap = count - rays_.TubeVertex(rings - 1, m - 1) - 1;
  for (int o = 1; o <= back_cap; ++o) {
    start_radii_[count - o] = previous_radii_[prev_count - o];
    start_valid_[count - o] = previous_valid_[prev_rings - 1];
  }
  // tube rings: interpolate the previous rings bracketing each parameter (both sorted)
  int p = 0;
  for (int i = 0; i < rings; ++i) {
    const double s = params_[i];
    while (p + 2 < prev_rings && previous_params_[p + 1] <= s) ++p;
    const double s0 = previous_params_[p], s1 = previous_params_[p + 1];
    const double f = std::clamp(s1 > s0 ? (s - s0) / (s1 - s0) : 0.0, 0.0, 1.0);
    const bool valid = previous_valid_[p] && previous_valid_[p + 1];
    for (int j = 0; j < m; ++j) {
      const double r0 = previous_radii_[first_tube + p * m + j];
      const double r1 = previous_radii_[first_tube + (p + 1) * m + j];
      start_radii_[rays_.TubeVertex(i, j)] = (1.0 - f) * r0 + f * r1;
      start_valid_[rays_.TubeVertex(i, j)] = valid;
    }
  }
}

void ConvolutionSkin::Solve(const std::vector<char>* active, const std::vector<double>* guess,
                            std::vector<double>* radii) {
  PrepareWindows(active);
  WarmStartGuesses();
  const int count = rays_.num_vertices();
  radii->resize(count);
  const std::vector<int>& ring_of = rays_.vertex_ring();
  const std::vector<Vec3>& origins = rays_.origins();
  const std::vector<Vec3>& dirs = rays_.directions();
  int evaluations = 0;
  long long total = 0;
  for (int v = 0; v < count; ++v) {
    const int ring = ring_of[v];
    if (active != nullptr && !(*active)[ring]) continue;
    double r0 = kColdStartFactor * radius_, slope = -2.0;
    if (start_valid_[v]) {
      r0 = start_radii_[v];
      slope = -2.5;  // a finite window falls off faster than 1 / r^2
    } else if (guess != nullptr) {
      r0 = (*guess)[v];
      slope = -2.5;
    }
    evaluations = 0;
    (*radii)[v] = SolveSeed(ring, origins[v], dirs[v], r0, slope, &evaluations);
    total += evaluations;
  }
  // remember this frame for the next warm start
  previous_params_ = params_;
  previous_radii_ = *radii;
  previous_valid_.assign(rays_.num_rings(), 1);
  if (active != nullptr) {
    for (int i = 0; i < rays_.num_rings(); ++i) previous_valid_[i] = (*active)[i];
  }
  has_previous_ = true;
  stats_.field_evaluations = total;
  stats_.rings = rays_.num_rings();
}

void ConvolutionSkin::Build(const Points& q, Mesh* out) {
  Prepare(q);
  Solve(nullptr, nullptr, &radii_);
  rays_.Emit(radii_, out);
  stats_.vertices = out->num_vertices();
  stats_.triangles = out->num_triangles();
}

}  // namespace viscera::skin
