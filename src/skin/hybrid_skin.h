#pragma once
/// Hybrid skin, the future work of France et al. 2005 (sec. 5): the convolution surface
/// inside a focus sphere (later the camera's view), the parametric generalized cylinder
/// outside. Both are built on the same rays (tube_rays.h): the convolution skin's adaptive
/// rings and frames. Each ring gets a weight w = smoothstep((rf + band - d) / band), d the
/// distance of its centre to the focus, and every vertex sits at radius
/// (1 - w) R_parametric(s) + w R_convolution. One mesh, shared vertices: no gap or crack at
/// the seams; w is continuous in the focus position: no popping when it moves. Only rings
/// with w > 0 pay for the convolution solve. With the convolution's prevent_folds (default)
/// the blended radii go through TubeRays::PreventFolds.
#include <vector>

#include "skin/convolution_skin.h"
#include "skin/skin.h"

namespace viscera::skin {

/// Smoothstep weight of the convolution surface for a ring centre at distance `distance`
/// from the focus: 1 inside focus_radius, 0 beyond focus_radius + transition, C1 between.
double FocusWeight(double distance, double focus_radius, double transition);

class HybridSkin final : public Skin {
 public:
  /// @throws InputError for invalid options.
  HybridSkin(double radius, const ParametricOptions& parametric,
             const ConvolutionOptions& convolution, const HybridOptions& hybrid);
  void Bind(int num_control_points) override;
  void Build(const Points& q, Mesh* out) override;
  const SkinStats& stats() const override { return stats_; }
  std::string name() const override { return "hybrid"; }

  /// Moves the focus sphere (centre in m, radius > 0 in m). @throws InputError if radius <= 0.
  void SetFocus(const Vec3& center, double radius);

  /// Per-vertex weight of the convolution surface in the last Build (#V).
  const std::vector<double>& vertex_weights() const { return vertex_weight_; }

 private:
  double r_min_, r_max_;
  HybridOptions hybrid_;
  bool prevent_folds_;  // the convolution's option, applied to the blended radii
  ConvolutionSkin convolution_;
  std::vector<double> ring_weight_, vertex_weight_, parametric_radii_, convolution_radii_, radii_;
  std::vector<char> active_;
  SkinStats stats_;
};

}  // namespace viscera::skin
