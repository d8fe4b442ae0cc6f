#pragma once
/// Moving frames (t, k, b) along the skeleton curve, for the ring-based skins.
///
/// The frames live on a fixed fine sampling of the curve (samples_per_segment per spline
/// segment); the frame at any other parameter is one more propagation step from the sample
/// below it. So the frame at a given s does not depend on which rings a skin happens to use
/// this frame (adaptive subdivision, hybrid), and the rings do not twist when that changes.
#include <vector>

#include "common/types.h"
#include "spline/catmull_rom.h"

namespace viscera::skin {

/// How a frame is carried from one curve sample to the next.
enum class FrameRule {
  /// Double reflection (Wang, Juettler, Zheng, Liu, "Computation of rotation minimizing
  /// frames", ACM TOG 2008): reflect the frame in the bisector plane of the chord, then in
  /// the plane swapping the reflected and the new tangent. Approximates the rotation-
  /// minimizing frame with O(h^4) global error and never degenerates.
  kDoubleReflection,
  /// France et al. 2005, section 4.1.1: b_s = t_s x k_{s-ds}, k_s = b_s x t_s (projection
  /// of the previous normal onto the new normal plane). First order in ds; breaks down when
  /// the tangent turns by 90 degrees or more between two samples.
  kProjection,
};

/// A point of the curve with its orthonormal right-handed frame, b = t x k.
struct Frame {
  Vec3 position = Vec3::Zero();
  Vec3 tangent = Vec3::UnitX();   ///< t, unit
  Vec3 normal = Vec3::UnitY();    ///< k, unit, perpendicular to t
  Vec3 binormal = Vec3::UnitZ();  ///< b = t x k
};

class FrameField {
 public:
  /// @pre samples_per_segment >= 1. @throws InputError otherwise.
  FrameField(FrameRule rule, int samples_per_segment);

  /// Recomputes the sampled frames for pose q (#N by 3, N = curve.num_points()). The first
  /// normal is the previous build's first normal projected onto the new normal plane
  /// (temporal coherence: the rings do not spin from frame to frame); on the first build it
  /// is the world axis least aligned with the first tangent, projected.
  /// @pre q.rows() == curve.num_points().
  void Build(const spline::CatmullRom& curve, const Points& q);

  /// Frame at curve parameter s in [0, 1] (clamped).
  Frame At(double s) const;

  FrameRule rule() const { return rule_; }
  const spline::CatmullRom* curve() const { return curve_; }
  const Points& control_points() const { return q_; }

 private:
  Frame Propagate(const Frame& from, double s) const;

  FrameRule rule_;
  int samples_per_segment_;
  const spline::CatmullRom* curve_ = nullptr;
  Points q_;                    // copy of the pose (#N by 3), small
  std::vector<Frame> samples_;  // at s = i / (#samples - 1)
  bool has_previous_ = false;
  Vec3 previous_first_normal_ = Vec3::UnitY();
};

/// Carries the normal `k` of a frame at (x0, t0) to the point x1 with unit tangent t1.
/// Returns the new unit normal (perpendicular to t1).
Vec3 CarryNormal(FrameRule rule, const Vec3& x0, const Vec3& t0, const Vec3& k0, const Vec3& x1,
                 const Vec3& t1);

}  // namespace viscera::skin
