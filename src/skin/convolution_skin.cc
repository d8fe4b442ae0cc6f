#include "skin/convolution_skin.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/check.h"
#include "common/target_clones.h"

namespace viscera::skin {
namespace {

constexpr double kColdStartFactor = 0.05;  // cold seeds start this close to the skeleton
constexpr double kMinRadiusFactor = 0.02;  // seeds stay within [0.02 R, 4 R] of their origin
constexpr double kMaxRadiusFactor = 4.0;
constexpr double kFoldMargin = 0.1;  // see TubeRays::PreventFolds

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
  ThrowUnless(options.skeleton_segments_per_span >= 1,
              "skeleton_segments_per_span must be >= 1, got ", options.skeleton_segments_per_span);
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
    skeleton_arc_[i] =
        i == 0 ? 0.0 : skeleton_arc_[i - 1] + (skeleton_[i] - skeleton_[i - 1]).norm();
  }
}

void ConvolutionSkin::Prepare(const Points& q) {
  CheckSnapshot(q, curve_.has_value() ? curve_->num_points() : 0);
  frames_.Build(*curve_, q);
  const double max_edge = options_.max_edge_factor > 0.0
                              ? options_.max_edge_factor * radius_
                              : 2.0 * std::numbers::pi * radius_ / options_.sides;
  AdaptiveRingParams(*curve_, q, radius_, max_edge, options_.max_angle, options_.max_depth,
                     &params_);
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
                            skeleton_arc_.begin()) -
           1;
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
    segments_[k].direction =
        len > 0.0 ? Vec3((skeleton_[k + 1] - skeleton_[k]) / len) : Vec3(Vec3::UnitX());
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

// The seeds' loop below vectorizes; AVX2's four doubles a lane halve its square roots and
// divisions where the CPU has them (no FMA: every result is the one of the plain build).
VISCERA_TARGET_CLONES("avx2")
void ConvolutionSkin::FieldBatch(int ring, const Vec3& origin, int n, const double* dx,
                                 const double* dy, const double* dz, const double* r,
                                 double* f) const {
  // Structure of arrays, segments outside and seeds inside: the inner loop has no branches
  // and vectorizes.
  double px[kBlock], py[kBlock], pz[kBlock];
  for (int j = 0; j < n; ++j) {
    px[j] = origin.x() + r[j] * dx[j];
    py[j] = origin.y() + r[j] * dy[j];
    pz[j] = origin.z() + r[j] * dz[j];
    f[j] = 0.0;
  }
  const double min_d2 = 1e-6 * radius_ * radius_;
  const Window& w = windows_[ring];
  auto add = [&](const KernelSegment& seg) {
    const double ax = seg.start.x(), ay = seg.start.y(), az = seg.start.z();
    const double ex = seg.direction.x(), ey = seg.direction.y(), ez = seg.direction.z();
    const double length = seg.length;
    for (int j = 0; j < n; ++j) {
      // (sin a1 - sin a2) / d^2, as SegmentField
      const double wx = px[j] - ax, wy = py[j] - ay, wz = pz[j] - az;
      const double t = wx * ex + wy * ey + wz * ez;
      const double d2 = std::max(wx * wx + wy * wy + wz * wz - t * t, min_d2);
      const double x1 = length - t;
      const double sin1 = x1 / std::sqrt(d2 + x1 * x1);
      const double sin0 = -t / std::sqrt(d2 + t * t);
      f[j] += (sin1 - sin0) / d2;
    }
  };
  add(w.first);
  if (w.k1 - w.k0 == 1) return;
  for (int k = w.k0 + 1; k < w.k1 - 1; ++k) add(segments_[k]);
  add(w.last);
}

long long ConvolutionSkin::SolveBlock(int ring, int begin, int end, std::vector<double>* radii) {
  // Secant iteration on y(x) = log f(origin + e^x dir) - log iso, x = log r, for all seeds of
  // the block at once: y is nearly linear in x (slope -2 for a long straight skeleton), so
  // one step from a warm start usually lands within tolerance.
  const double x_min = std::log(kMinRadiusFactor * radius_);
  const double x_max = std::log(kMaxRadiusFactor * radius_);
  const double tol = options_.tolerance * radius_;
  const double log_iso = log_iso_[ring];
  const Vec3& origin = rays_.origins()[begin];
  const std::vector<Vec3>& dirs = rays_.directions();
  const int n = end - begin;
  VISCERA_DEMAND(0 < n && n <= kBlock);
  double x[kBlock], y[kBlock], slope[kBlock], r_now[kBlock], r_new[kBlock];  // r = e^x
  int evals[kBlock];
  // active seeds, compacted: their index in the block and SoA directions / radii / fields
  int idx[kBlock];
  double dx[kBlock] = {}, dy[kBlock] = {}, dz[kBlock] = {}, r[kBlock] = {}, f[kBlock];
  for (int j = 0; j < n; ++j) {
    const int v = begin + j;
    double r0 = kColdStartFactor * radius_;
    slope[j] = -2.0;
    if (start_valid_[v]) {
      r0 = start_radii_[v];
      slope[j] = -2.5;  // a finite window falls off faster than 1 / r^2
    } else if (guess_ != nullptr) {
      r0 = (*guess_)[v];
      slope[j] = -2.5;
    }
    x[j] = std::clamp(std::log(r0), x_min, x_max);
    idx[j] = j;
    evals[j] = 1;
    dx[j] = dirs[v].x();
    dy[j] = dirs[v].y();
    dz[j] = dirs[v].z();
    r[j] = std::exp(x[j]);
    r_now[j] = r[j];
  }
  FieldBatch(ring, origin, n, dx, dy, dz, r, f);
  for (int j = 0; j < n; ++j) y[j] = std::log(std::max(f[j], 1e-300)) - log_iso;
  long long total = n;
  int active = n;
  double x_new[kBlock];
  while (active > 0) {
    // step every active seed; retire the converged ones
    int kept = 0;
    for (int a = 0; a < active; ++a) {
      const int j = idx[a];
      const double xn = std::clamp(x[j] - y[j] / slope[j], x_min, x_max);
      const double rn = std::exp(xn);
      if (std::abs(rn - r_now[j]) < tol || evals[j] >= options_.max_iterations) {
        (*radii)[begin + j] = rn;
        continue;
      }
      x_new[j] = xn;
      r_new[j] = rn;
      idx[kept] = j;
      dx[kept] = dirs[begin + j].x();
      dy[kept] = dirs[begin + j].y();
      dz[kept] = dirs[begin + j].z();
      r[kept] = rn;
      ++kept;
    }
    active = kept;
    if (active == 0) break;
    FieldBatch(ring, origin, active, dx, dy, dz, r, f);
    total += active;
    for (int a = 0; a < active; ++a) {
      const int j = idx[a];
      const double yn = std::log(std::max(f[a], 1e-300)) - log_iso;
      const double secant = (yn - y[j]) / (x_new[j] - x[j]);
      // keep the last slope if the secant is not a usable (decreasing) one
      if (std::isfinite(secant) && secant < -0.25) slope[j] = secant;
      x[j] = x_new[j];
      r_now[j] = r_new[j];
      y[j] = yn;
      ++evals[j];
    }
  }
  return total;
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
  guess_ = guess;
  long long total = 0;
  // blocks of consecutive vertices on one ray origin (a ring, or an end ring with its cap)
  for (int begin = 0; begin < count;) {
    const int ring = ring_of[begin];
    int end = begin + 1;
    while (end < count && end - begin < kBlock && ring_of[end] == ring) ++end;
    if (active == nullptr || (*active)[ring]) total += SolveBlock(ring, begin, end, radii);
    begin = end;
  }
  guess_ = nullptr;
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
  // (the warm start keeps the unclamped iso-surface radii)
  if (options_.prevent_folds) rays_.PreventFolds(kFoldMargin, &radii_);
  rays_.Emit(radii_, out);
  stats_.vertices = out->num_vertices();
  stats_.triangles = out->num_triangles();
}

}  // namespace viscera::skin
