#pragma once
/// The skin interface: bind once to a skeleton size, then build a mesh from each skeleton
/// snapshot (control points, #N by 3), reusing buffers and the previous mesh. Skins know only
/// the control points, the tube radius and their own options; never mechanics state.
#include <memory>
#include <string>

#include "common/types.h"
#include "skin/frame_field.h"
#include "skin/mesh.h"

namespace viscera::skin {

/// Generalized cylinder (France et al. 2005, sec. 4.1).
struct ParametricOptions {
  double radius_min_factor = 0.9;  ///< Rmin = factor * radius
  double radius_max_factor = 1.1;  ///< Rmax = factor * radius
  int rings_per_segment = 8;       ///< tessellation step ds = 1 / rings_per_segment
  int sides = 16;                  ///< vertices per ring
  int cap_rings = 4;               ///< rings of a hemispherical end cap (1 = flat fan)
  FrameRule frame_rule = FrameRule::kDoubleReflection;
  int frame_samples_per_segment = 8;
  /// Shorten the rays on the inner side of bends tighter than the radius so that rings do
  /// not fold over (tube_rays.h, FoldLimit). Off by default: the paper's skin folds there.
  bool prevent_folds = false;
};

/// Convolution surface with the Cani-Hornus segment kernel and local convolution
/// (France et al. 2005, sec. 4.3; Hornus, Angelidis, Cani 2003; Angelidis et al. 2002).
struct ConvolutionOptions {
  int sides = 32;  ///< seeds per ring
  int cap_rings = 6;
  double neighbourhood_factor = 1.8;   ///< D = factor * radius, must be < 2 (D < 2R)
  bool local = true;                   ///< false: whole skeleton (blends non-consecutive parts)
  int skeleton_segments_per_span = 4;  ///< polyline segments per spline segment
  double max_edge_factor = 0.0;  ///< adaptive rings: max outer edge / radius (0: 2 pi / sides)
  double max_angle = 0.35;       ///< adaptive rings: max tangent turn per ring step (rad)
  int max_depth = 7;             ///< adaptive rings: bisection levels per spline segment
  double tolerance = 1e-4;       ///< stop when the radial step < tolerance * radius
  int max_iterations = 12;       ///< field evaluations per seed, at most
  bool warm_start = true;        ///< seeds start from their previous radius
  /// Shorten rays on the inner side of bends tighter than the surface's radius so that rings
  /// do not fold over: the surface creases there instead of turning inside out.
  bool prevent_folds = true;
  FrameRule frame_rule = FrameRule::kDoubleReflection;
  int frame_samples_per_segment = 8;
};

/// Point-skeleton implicit surface, marching cubes in a narrow band (sec. 4.2).
struct ImplicitOptions {
  double spacing_factor = 0.4;    ///< primitive spacing along the curve / radius
  double support_factor = 2.0;    ///< compact support radius of a primitive / radius
  double cell_factor = 0.25;      ///< marching-cubes cell size / radius
  bool blending_graph = true;     ///< false: every primitive blends with every other
  double blend_arc_factor = 3.0;  ///< primitives closer than this * radius along the curve blend
};

/// Convolution surface inside a focus sphere, parametric outside, radii blended over a
/// transition band (smoothstep in the distance of the ring centre to the focus).
struct HybridOptions {
  Vec3 focus = Vec3::Zero();
  double focus_radius = 0.1;  ///< m
  double transition = 0.05;   ///< width of the blend band, m
};

struct SkinOptions {
  double radius = 0.0125;  ///< tube radius R (m), the scene's `radius`
  ParametricOptions parametric;
  ConvolutionOptions convolution;
  ImplicitOptions implicit;
  HybridOptions hybrid;
};

/// Counters of the last Build, for tests and benchmarks.
struct SkinStats {
  int vertices = 0;
  int triangles = 0;
  long long field_evaluations = 0;  ///< implicit skins: field evaluations (seed iterations)
  int rings = 0;                    ///< ring-based skins
  int primitives = 0;               ///< point-skeleton skin
};

class Skin {
 public:
  virtual ~Skin() = default;
  /// Precomputes what depends only on the skeleton size. Must be called before Build and
  /// again if the number of control points changes; drops temporal-coherence state.
  /// @pre num_control_points >= 4. @throws InputError otherwise.
  virtual void Bind(int num_control_points) = 0;
  /// Builds the mesh of one skeleton snapshot into *out (its buffers are reused).
  /// @pre Bind(q.rows()) was called. @throws InputError if q has another row count.
  virtual void Build(const Points& q, Mesh* out) = 0;
  virtual const SkinStats& stats() const = 0;
  virtual std::string name() const = 0;
};

/// The names MakeSkin knows, and that list as one string for messages.
inline constexpr const char* kSkinNames[] = {"parametric", "implicit", "convolution", "hybrid"};
inline constexpr char kSkinNameList[] = "parametric, implicit, convolution or hybrid";
bool IsSkinName(const std::string& name);

/// Creates a skin by name: "parametric", "implicit", "convolution" or "hybrid".
/// @throws InputError for an unknown name or invalid options.
std::unique_ptr<Skin> MakeSkin(const std::string& name, const SkinOptions& options);

/// Validates options shared by all skins. @throws InputError with the offending values.
void ValidateOptions(const SkinOptions& options);

/// Checks a skeleton snapshot before a skin reads it: `bound_rows` control points (0: the
/// skin was never bound), all finite. A NaN from a diverged simulation must not reach the
/// mesh. @throws InputError naming the problem.
void CheckSnapshot(const Points& q, int bound_rows);

}  // namespace viscera::skin
