#pragma once
/// Implicit skin from point skeletons (France et al. 2005, sec. 4.2).
///
/// Primitives: points spread uniformly by arc length along the curve, spacing
/// L / ceil(L / (spacing_factor R)), so their number follows the length (the paper places
/// them "at intervals function of the segment length and the radius"). Field of a primitive:
/// the compact "soft object" kernel w (1 - d^2 / rho^2)^3 for d < rho (Wyvill, McPheeters,
/// Wyvill 1986), rho = support_factor R; weight w = actual spacing / nominal spacing so the
/// field of a straight run does not change when a primitive is added. Iso-value: the field
/// of an infinite straight line of primitives at distance R, (1 / spacing) integral of the
/// kernel along the line (computed at construction), so a straight tube has radius R.
///
/// Blending graph (Cani 1993; France et al. 2005, sec. 4.2.2): at a point p the contributing
/// primitives are split into groups, runs of consecutive indices whose arc-length gap stays
/// below blend_arc_factor R; primitives blend (sum) inside a group, and groups combine by
/// max (union). So two parts of the tube that are not consecutive along it never merge,
/// even when they touch, while consecutive primitives blend smoothly.
///
/// Polygonization: marching cubes in a narrow band (marching_cubes.h), seeded from rays
/// perpendicular to the curve, cell = cell_factor R.
#include <optional>
#include <vector>

#include "skin/marching_cubes.h"
#include "skin/skin.h"
#include "spline/arc_length.h"

namespace viscera::skin {

/// The soft-object kernel (1 - d^2 / rho^2)^3 for d^2 < rho^2, else 0.
inline double SoftObjectKernel(double d2, double rho2) {
  if (d2 >= rho2) return 0.0;
  const double a = 1.0 - d2 / rho2;
  return a * a * a;
}

/// Field of point primitives with an optional blending graph. Rebuilt per frame. Value()
/// fills a per-frame cache: one thread at a time.
class PointSkeletonField final : public ScalarField {
 public:
  /// @param block edge of the cubes whose candidate primitives are cached (m): smaller
  ///        blocks have shorter candidate lists, larger ones fewer lists to build.
  PointSkeletonField(double support, bool blending_graph, double blend_gap, double block);
  /// Takes primitives (#P, in curve order, arc-length spacing `spacing`) of weight `weight`.
  void Reset(const std::vector<Vec3>& points, double spacing, double weight);
  double Value(const Vec3& p) const override;

 private:
  double support_, support2_, blend_gap_, block_;
  bool blending_graph_;
  int max_index_gap_ = 1;
  double weight_ = 1.0;
  const std::vector<Vec3>* points_ = nullptr;
  // uniform grid over the primitives (cell 2 * support: a block's reach spans 2-3 cells per
  // axis): sorted (key, index) and look-up
  double GridCell() const { return 2.0 * support_; }
  std::vector<std::pair<uint64_t, int>> sorted_;
  FlatHashMap<std::pair<int, int>> cells_;  // key -> [begin, end) in sorted_
  // Candidate primitives per block, filled lazily during a frame (so
  // Value is not thread-safe): block key -> [begin, end) in pool_, sorted by index.
  std::pair<int, int> Candidates(const Vec3& p) const;
  mutable FlatHashMap<std::pair<int, int>> blocks_;
  mutable std::vector<int> pool_;
  mutable std::vector<double> pool_x_, pool_y_, pool_z_;  // coordinates of pool_ entries
};

class ImplicitSkin final : public Skin {
 public:
  /// @throws InputError for invalid options.
  ImplicitSkin(double radius, const ImplicitOptions& options);
  void Bind(int num_control_points) override;
  void Build(const Points& q, Mesh* out) override;
  const SkinStats& stats() const override { return stats_; }
  std::string name() const override { return "implicit"; }

  double iso_value() const { return iso_; }
  const std::vector<Vec3>& primitives() const { return primitives_; }
  /// True if the last Build stopped at its cell budget (the mesh then has holes).
  bool hit_budget() const { return polygonizer_.hit_budget(); }

 private:
  double radius_;
  ImplicitOptions options_;
  double spacing_, iso_;
  std::optional<spline::CatmullRom> curve_;
  spline::ArcLengthTable arc_table_;
  std::vector<Vec3> primitives_, seeds_;
  PointSkeletonField field_;
  NarrowBandPolygonizer polygonizer_;
  SkinStats stats_;
};

}  // namespace viscera::skin
