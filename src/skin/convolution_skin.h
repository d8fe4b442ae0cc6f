#pragma once
/// Convolution-surface skin (France et al. 2005, sec. 4.3): the skeleton spline approximated
/// by a polyline of segments, each contributing the closed-form Cani-Hornus kernel
/// (segment_kernel.h); local convolution (Angelidis, Cani et al. 2002): the seed attached to
/// curve parameter u only feels the skeleton within arc length D/2 of u, D < 2R, so parts of
/// the tube that are not consecutive along it never blend and no bulges form.
///
/// Sampling: seeds on rays from the skeleton (tube_rays.h), one ring of `sides` seeds per
/// curve parameter of an adaptive ring set (subdivided by edge length and tangent turn).
/// Each seed moves along its ray to the iso-surface by a secant iteration on
/// log f(log r) (nearly linear: f ~ 2 / r^2 near a straight skeleton). Seeds start from
/// their previous radius (temporal coherence), interpolated along the curve when the ring
/// set changed; on the first frame they start from the skeleton (r = 0.05 R).
///
/// Iso-value: per ring, the field a straight skeleton covering the same (end-clipped) window
/// has at distance R, so a straight tube has radius R exactly, up to its ends.
#include <optional>
#include <vector>

#include "skin/segment_kernel.h"
#include "skin/skin.h"
#include "skin/tube_rays.h"

namespace viscera::skin {

class ConvolutionSkin final : public Skin {
 public:
  /// @throws InputError for invalid options (D >= 2R, tolerance <= 0, ...).
  ConvolutionSkin(double radius, const ConvolutionOptions& options);
  void Bind(int num_control_points) override;
  void Build(const Points& q, Mesh* out) override;
  const SkinStats& stats() const override { return stats_; }
  std::string name() const override { return "convolution"; }

  /// Forgets the previous frame: the next Build starts every seed from the skeleton.
  void ResetWarmStart() { has_previous_ = false; }

  // --- pieces the hybrid skin composes ---
  /// Frames, adaptive rings, rays and the segment skeleton of pose q (#N by 3).
  void Prepare(const Points& q);
  /// Moves the seeds of the rings flagged in `active` (#K, null = all) to the surface and
  /// writes their radii into *radii (#V; other entries untouched). `guess` (#V, optional)
  /// is the start radius of seeds without a previous position. Saves the radii for the
  /// next frame's warm start.
  void Solve(const std::vector<char>* active, const std::vector<double>* guess,
             std::vector<double>* radii);
  const TubeRays& rays() const { return rays_; }
  const std::optional<spline::CatmullRom>& curve() const { return curve_; }

  /// Field at p as seen by ring `ring` (its local window, or the whole skeleton), for the
  /// rings the last Solve moved. For tests and tools.
  double Field(int ring, const Vec3& p) const;
  /// The ring's iso-value.
  double IsoValue(int ring) const { return iso_[ring]; }

 private:
  void BuildSkeleton(const Points& q);
  void PrepareWindows(const std::vector<char>* active);
  void WarmStartGuesses();
  static constexpr int kBlock = 64;  // seeds solved together (SoA batch)
  // Field at origin + r[j] * (dx, dy, dz)[j] for j < n, n <= kBlock.
  void FieldBatch(int ring, const Vec3& origin, int n, const double* dx, const double* dy,
                  const double* dz, const double* r, double* f) const;
  // Moves the seeds [begin, end) (one ring, one ray origin) to the surface; returns the
  // number of field evaluations.
  long long SolveBlock(int ring, int begin, int end, std::vector<double>* radii);

  double radius_;
  ConvolutionOptions options_;
  double neighbourhood_;  // D (m)
  std::optional<spline::CatmullRom> curve_;
  FrameField frames_;
  TubeRays rays_;
  std::vector<double> params_;
  // polyline skeleton: points and cumulative arc length
  std::vector<Vec3> skeleton_;
  std::vector<double> skeleton_arc_;
  // Per ring: the skeleton segments [k0, k1) overlapping its window, the first and last
  // clipped to it (first alone when k1 - k0 == 1); the interior ones are segments_[k].
  struct Window {
    int k0 = 0, k1 = 1;
    KernelSegment first, last;
  };
  std::vector<Window> windows_;
  std::vector<KernelSegment> segments_;
  std::vector<double> iso_, log_iso_;
  // temporal coherence
  bool has_previous_ = false;
  std::vector<double> previous_params_, previous_radii_, start_radii_;
  std::vector<char> previous_valid_, start_valid_;
  std::vector<double> radii_;
  const std::vector<double>* guess_ = nullptr;  // during Solve only
  SkinStats stats_;
};

}  // namespace viscera::skin
