#pragma once
/// The shared layout of the ring-based skins (parametric, convolution, hybrid): a tube of K
/// rings of M vertices plus two end caps of C-1 rings and a pole each. Every vertex sits on
/// a ray origin + r * dir; the skins only differ in how they choose r. Because the hybrid
/// blends r along the same rays, its parametric and convolution parts share their vertices
/// at the seams and cannot crack.
///
/// Vertex order: front pole, front cap rings (pole side first), tube rings 0..K-1, back cap
/// rings (tube side first), back pole. Ring vertex j sits at angle 2 pi j / M from the frame
/// normal k towards b; with b = t x k the triangles (ring i, j), (i, j+1), (i+1, j+1) face
/// outwards.
#include <vector>

#include "common/types.h"
#include "skin/frame_field.h"
#include "skin/mesh.h"

namespace viscera::skin {

class TubeRays {
 public:
  /// @pre sides >= 3, cap_rings >= 1 (1 = a flat fan to the pole). @throws InputError.
  TubeRays(int sides, int cap_rings);

  /// Rebuilds the rays for tube rings at curve parameters `ring_params` (K >= 2, increasing,
  /// first 0 and last 1) from the frames. Triangles are rebuilt only when K changes.
  void Build(const FrameField& frames, const std::vector<double>& ring_params);

  int sides() const { return sides_; }
  int cap_rings() const { return cap_rings_; }
  int num_rings() const { return static_cast<int>(ring_params_.size()); }
  int num_vertices() const { return static_cast<int>(origins_.size()); }
  const std::vector<double>& ring_params() const { return ring_params_; }
  /// Ring centres (#K), on the curve.
  const std::vector<Vec3>& ring_centers() const { return ring_centers_; }
  /// Per vertex: ray origin (its ring centre, or the end point for caps) and unit direction.
  const std::vector<Vec3>& origins() const { return origins_; }
  const std::vector<Vec3>& directions() const { return directions_; }
  /// Per vertex: the tube ring it is attached to (caps attach to ring 0 or K-1).
  const std::vector<int>& vertex_ring() const { return vertex_ring_; }
  /// Largest radius the vertex's ray can take without its ring folding over the next on the
  /// inner side of a bend: rings cross where 1 - r (kappa . dir) <= 0, kappa the curvature
  /// vector (1/m) of the ring's centre, so the limit is (1 - margin) / (kappa . dir) when
  /// kappa . dir > 0, else +infinity. margin in (0, 1).
  double FoldLimit(int vertex, double margin) const;
  /// Shortens rays so that rings do not fold over on the inner side of tight bends: each ray
  /// is capped at FoldLimit(v, margin), then, walking each side line from the first ring to
  /// the last, a vertex that would not advance along the curve by at least `margin` times
  /// the ring step (discrete folds where the curvature changes between rings) is pulled in
  /// until it does. Caps are left alone. The surface creases there instead of turning
  /// inside out. @pre radii->size() == num_vertices().
  void PreventFolds(double margin, std::vector<double>* radii) const;
  /// Curvature vectors of the ring centres (#K, 1/m, pointing to the centre of curvature).
  const std::vector<Vec3>& ring_curvatures() const { return ring_curvatures_; }
  /// Per vertex: true for the cap vertices (poles included).
  bool IsCap(int vertex) const {
    return vertex < FirstTubeVertex() || vertex >= FirstTubeVertex() + num_rings() * sides_;
  }
  int FirstTubeVertex() const { return 1 + (cap_rings_ - 1) * sides_; }
  /// Vertex index of tube ring i, side j.
  int TubeVertex(int ring, int side) const { return FirstTubeVertex() + ring * sides_ + side; }
  const std::vector<Eigen::Vector3i>& triangles() const { return triangles_; }

  /// Writes positions origin + radii[v] * dir, the triangles and vertex normals.
  /// @pre radii.size() == num_vertices().
  void Emit(const std::vector<double>& radii, Mesh* out) const;

 private:
  void BuildTriangles();

  int sides_, cap_rings_;
  std::vector<double> ring_params_;
  std::vector<Vec3> ring_centers_, ring_curvatures_, origins_, directions_;
  std::vector<int> vertex_ring_;
  std::vector<Eigen::Vector3i> triangles_;
  int triangles_for_rings_ = -1;
  std::vector<double> cos_, sin_;
};

/// Paper-style rings: `per_segment` rings per spline segment, uniform in the local
/// parameter (s = (j + i / per_segment) / (N - 1)), plus s = 1. Clears and fills `params`.
void UniformRingParams(int num_segments, int per_segment, std::vector<double>* params);

/// Adaptive rings: each spline segment starts as one interval and is bisected recursively
/// (dyadic, so a ring's parameter is stable from frame to frame) while the estimated length
/// of its outer-side edges, chord + turning angle * radius, exceeds max_edge or its tangents
/// turn by more than max_angle, up to max_depth levels. Clears and fills `params`.
/// @pre q.rows() == curve.num_points().
void AdaptiveRingParams(const spline::CatmullRom& curve, const Points& q, double radius,
                        double max_edge, double max_angle, int max_depth,
                        std::vector<double>* params);

}  // namespace viscera::skin
