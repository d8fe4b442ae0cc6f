#pragma once
/// Parametric skin: a generalized cylinder around the skeleton (France et al. 2005, sec.
/// 4.1.1). Circles in the normal plane with radius R(s) = Rmin + cos^2(pi s) dR, s in [0, 1]
/// between two control points, dR = Rmax - Rmin; rings joined into facets; hemispherical
/// end caps of radius R at the ends (= Rmax).
///
/// Rings fold over (facets on the inner side turn inside out) where the curvature radius of
/// the skeleton drops below the ring radius, i.e. when kappa * Rmax >= 1 (see
/// docs/skins.md and the tests).
#include <optional>
#include <vector>

#include "skin/skin.h"
#include "skin/tube_rays.h"

namespace viscera::skin {

/// Ring radius between two control points: R(u) = Rmin + cos^2(pi u) (Rmax - Rmin), u the
/// local parameter of the segment (France et al. 2005, sec. 4.1.1).
double ParametricRadius(double r_min, double r_max, double u);

class ParametricSkin final : public Skin {
 public:
  /// @throws InputError for invalid options.
  ParametricSkin(double radius, const ParametricOptions& options);
  void Bind(int num_control_points) override;
  void Build(const Points& q, Mesh* out) override;
  const SkinStats& stats() const override { return stats_; }
  std::string name() const override { return "parametric"; }

  /// Radii of the rays of `rays` (ring radius R(s) on tube and cap vertices). For the hybrid.
  void RadiiFor(const TubeRays& rays, std::vector<double>* radii) const;
  const TubeRays& rays() const { return rays_; }

 private:
  double r_min_, r_max_;
  ParametricOptions options_;
  std::optional<spline::CatmullRom> curve_;
  FrameField frames_;
  TubeRays rays_;
  std::vector<double> params_, radii_;
  mutable std::vector<double> ring_radii_;  // scratch of RadiiFor
  SkinStats stats_;
};

}  // namespace viscera::skin
