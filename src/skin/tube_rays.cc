#include "skin/tube_rays.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "common/check.h"

namespace viscera::skin {

TubeRays::TubeRays(int sides, int cap_rings) : sides_(sides), cap_rings_(cap_rings) {
  ThrowUnless(sides >= 3, "a tube needs at least 3 sides, got ", sides);
  ThrowUnless(cap_rings >= 1, "cap rings must be >= 1, got ", cap_rings);
  cos_.resize(sides);
  sin_.resize(sides);
  for (int j = 0; j < sides; ++j) {
    const double theta = 2.0 * std::numbers::pi * j / sides;
    cos_[j] = std::cos(theta);
    sin_[j] = std::sin(theta);
  }
}

void TubeRays::Build(const FrameField& frames, const std::vector<double>& ring_params) {
  const int k = static_cast<int>(ring_params.size());
  ThrowUnless(k >= 2, "a tube needs at least 2 rings, got ", k);
  ring_params_ = ring_params;
  const int m = sides_, c = cap_rings_;
  const int count = 2 + (2 * (c - 1) + k) * m;
  ring_centers_.resize(k);
  ring_curvatures_.resize(k);
  origins_.resize(count);
  directions_.resize(count);
  vertex_ring_.resize(count);

  // tube rings
  Frame first, last;
  for (int i = 0; i < k; ++i) {
    const Frame f = frames.At(ring_params[i]);
    if (i == 0) first = f;
    if (i == k - 1) last = f;
    ring_centers_[i] = f.position;
    // curvature vector (P'' - (P'' . t) t) / |P'|^2
    const Vec3 d1 = frames.curve()->Tangent(frames.control_points(), ring_params[i]);
    const Vec3 d2 = frames.curve()->SecondDerivative(frames.control_points(), ring_params[i]);
    const double speed2 = d1.squaredNorm();
    ring_curvatures_[i] =
        speed2 > 0.0 ? Vec3((d2 - d2.dot(f.tangent) * f.tangent) / speed2) : Vec3(Vec3::Zero());
    for (int j = 0; j < m; ++j) {
      const int v = TubeVertex(i, j);
      origins_[v] = f.position;
      directions_[v] = cos_[j] * f.normal + sin_[j] * f.binormal;
      vertex_ring_[v] = i;
    }
  }
  // caps: polar angle phi = (pi/2) * level / C, tilted away from the tube along -t / +t
  auto fill_cap = [&](const Frame& f, double sign, int ring, int level, int first_vertex) {
    const double phi = 0.5 * std::numbers::pi * level / c;
    for (int j = 0; j < m; ++j) {
      const Vec3 radial = cos_[j] * f.normal + sin_[j] * f.binormal;
      origins_[first_vertex + j] = f.position;
      directions_[first_vertex + j] = std::cos(phi) * radial + sign * std::sin(phi) * f.tangent;
      vertex_ring_[first_vertex + j] = ring;
    }
  };
  for (int level = 1; level < c; ++level) {
    fill_cap(first, -1.0, 0, level, 1 + (c - 1 - level) * m);
    fill_cap(last, 1.0, k - 1, level, TubeVertex(k - 1, 0) + level * m);
  }
  origins_[0] = first.position;
  directions_[0] = -first.tangent;
  vertex_ring_[0] = 0;
  origins_[count - 1] = last.position;
  directions_[count - 1] = last.tangent;
  vertex_ring_[count - 1] = k - 1;

  if (triangles_for_rings_ != k) BuildTriangles();
}

double TubeRays::FoldLimit(int vertex, double margin) const {
  const double inward = ring_curvatures_[vertex_ring_[vertex]].dot(directions_[vertex]);
  return inward > 0.0 ? (1.0 - margin) / inward : std::numeric_limits<double>::infinity();
}

void TubeRays::PreventFolds(double margin, std::vector<double>* radii) const {
  VISCERA_DEMAND(static_cast<int>(radii->size()) == num_vertices());
  std::vector<double>& r = *radii;
  for (int v = 0; v < num_vertices(); ++v) r[v] = std::min(r[v], FoldLimit(v, margin));
  const int k = num_rings(), m = sides_;
  for (int i = 1; i < k; ++i) {
    const Vec3 step = ring_centers_[i] - ring_centers_[i - 1];
    const double step2 = step.squaredNorm();
    if (step2 <= 0.0) continue;
    for (int j = 0; j < m; ++j) {
      const int v = TubeVertex(i, j), u = TubeVertex(i - 1, j);
      const Vec3 previous = origins_[u] + r[u] * directions_[u];
      // advance (origin + r dir - previous) . step >= margin |step|^2, linear in r
      const double a = (origins_[v] - previous).dot(step) - margin * step2;
      const double b = directions_[v].dot(step);
      if (a + r[v] * b >= 0.0 || b >= 0.0) continue;
      r[v] = std::max(0.0, a / -b);
    }
  }
}

void TubeRays::BuildTriangles() {
  const int k = num_rings(), m = sides_;
  const int rings_total = k + 2 * (cap_rings_ - 1);
  const int back_pole = 1 + rings_total * m;
  triangles_.clear();
  triangles_.reserve(2 * m * rings_total);
  auto at = [m](int ring, int side) { return 1 + ring * m + (side % m); };
  // front fan (pole, r[j+1], r[j])
  for (int j = 0; j < m; ++j) triangles_.emplace_back(0, at(0, j + 1), at(0, j));
  // strips between consecutive rings, (a, b, c) and (a, c, d)
  for (int r = 0; r + 1 < rings_total; ++r) {
    for (int j = 0; j < m; ++j) {
      const int a = at(r, j), b = at(r, j + 1), cc = at(r + 1, j + 1), d = at(r + 1, j);
      triangles_.emplace_back(a, b, cc);
      triangles_.emplace_back(a, cc, d);
    }
  }
  // back fan (r[j], r[j+1], pole)
  for (int j = 0; j < m; ++j) {
    triangles_.emplace_back(at(rings_total - 1, j), at(rings_total - 1, j + 1), back_pole);
  }
  triangles_for_rings_ = k;
}

void TubeRays::Emit(const std::vector<double>& radii, Mesh* out) const {
  VISCERA_DEMAND(static_cast<int>(radii.size()) == num_vertices());
  const int count = num_vertices();
  out->positions.resize(count);
  for (int v = 0; v < count; ++v) out->positions[v] = origins_[v] + radii[v] * directions_[v];
  out->triangles = triangles_;
  ComputeVertexNormals(out);
  // where each vertex sits on the tissue: its ring's parameter (caps: their end's) and its side
  // (ring after ring, the poles first and last: no division per vertex)
  out->surface.resize(count);
  const int first = FirstTubeVertex();
  std::vector<double> angles(static_cast<size_t>(sides_));
  for (int side = 0; side < sides_; ++side) {
    angles[static_cast<size_t>(side)] = 2.0 * std::numbers::pi * side / sides_;
  }
  out->surface.front() = {0.0, angles[0]};
  out->surface.back() = {1.0, angles[0]};
  const int tube_end = first + num_rings() * sides_;
  for (int v = 1; v + 1 < count; v += sides_) {
    const double s = v < first      ? 0.0
                     : v < tube_end ? ring_params_[static_cast<size_t>((v - first) / sides_)]
                                    : 1.0;
    for (int side = 0; side < sides_; ++side) {
      out->surface[static_cast<size_t>(v + side)] = {s, angles[static_cast<size_t>(side)]};
    }
  }
  // BuildTriangles: the front fan and the strips of the front cap's rings come first
  out->tube = {num_rings(), sides_, first, sides_ + 2 * sides_ * (cap_rings_ - 1)};
}

void UniformRingParams(int num_segments, int per_segment, std::vector<double>* params) {
  ThrowUnless(per_segment >= 1, "rings per segment must be >= 1, got ", per_segment);
  params->clear();
  const int total = num_segments * per_segment;
  for (int i = 0; i <= total; ++i) params->push_back(static_cast<double>(i) / total);
}

void AdaptiveRingParams(const spline::CatmullRom& curve, const Points& q, double radius,
                        double max_edge, double max_angle, int max_depth,
                        std::vector<double>* params) {
  ThrowUnless(max_edge > 0.0 && max_angle > 0.0 && max_depth >= 0,
              "adaptive rings need max_edge > 0, max_angle > 0, max_depth >= 0; got ", max_edge,
              ", ", max_angle, ", ", max_depth);
  params->clear();
  const int n = curve.num_segments();
  // Explicit stack: (s0, s1, depth) intervals, right half pushed first so output is sorted.
  struct Interval {
    double s0, s1;
    Vec3 p0, p1, t0, t1;
    int depth;
  };
  std::vector<Interval> stack;
  auto unit_tangent = [&](double s) {
    const Vec3 t = curve.Tangent(q, s);
    const double len = t.norm();
    return len > 1e-12 ? Vec3(t / len) : Vec3(Vec3::Zero());
  };
  for (int j = 0; j < n; ++j) {
    const double s0 = static_cast<double>(j) / n, s1 = static_cast<double>(j + 1) / n;
    stack.push_back({s0, s1, curve.Position(q, s0), curve.Position(q, s1), unit_tangent(s0),
                     unit_tangent(s1), 0});
    while (!stack.empty()) {
      const Interval iv = stack.back();
      stack.pop_back();
      const double chord = (iv.p1 - iv.p0).norm();
      const double angle = std::acos(std::clamp(iv.t0.dot(iv.t1), -1.0, 1.0));
      // Outer-side edge of the ring strip: arc length plus turning angle times radius.
      const bool split =
          iv.depth < max_depth && (chord + angle * radius > max_edge || angle > max_angle);
      if (!split) {
        params->push_back(iv.s0);
        continue;
      }
      const double sm = 0.5 * (iv.s0 + iv.s1);
      const Vec3 pm = curve.Position(q, sm), tm = unit_tangent(sm);
      stack.push_back({sm, iv.s1, pm, iv.p1, tm, iv.t1, iv.depth + 1});
      stack.push_back({iv.s0, sm, iv.p0, pm, iv.t0, tm, iv.depth + 1});
    }
  }
  params->push_back(1.0);
}

}  // namespace viscera::skin
