#pragma once
/// How much of each target the laparoscope sees: rays from the lens to every sample point of
/// the target, blocked by the intestine (a tube of its radius around the sphere chain's
/// centres: capsules between neighbouring centres). A sample counts as seen when it faces the
/// lens, lies inside the view cone and no capsule crosses its ray. Cost per evaluation: at
/// most samples x (capsules near the target's view cone) segment-segment distances; see
/// docs/assessment.md for the figures.
#include <string>
#include <vector>

#include "common/types.h"
#include "mechanics/task_params.h"

namespace viscera::assessment {

/// The laparoscope as the exposure needs it (the renderer's Laparoscope carries the same).
struct View {
  Vec3 eye = Vec3::Zero();       ///< lens (m)
  Vec3 look_at = Vec3::UnitY();  ///< a point on the optical axis (m)
  Vec3 up = Vec3::UnitZ();
  double fov_y_deg = 70.0;    ///< vertical field of view
  double aspect = 4.0 / 3.0;  ///< width / height of the frame
};

/// Which samples of one target are seen and what that cost.
struct TargetExposure {
  double fraction = 0.0;    ///< seen / samples, 0..1
  std::vector<bool> seen;   ///< per sample, in TargetSamples order
  int capsules_tested = 0;  ///< capsules that survived the cone cull
};

class ExposureEvaluator {
 public:
  /// Precomputes the sample points of every target (`targets` as in TaskParams).
  /// @param tube_radius the intestine's radius (m), > 0.
  ExposureEvaluator(const std::vector<mechanics::TargetParams>& targets, double tube_radius);

  /// Exposure of target `index` seen from `view` with the tube's centre line through `centres`
  /// (the sphere chain's centres in order along the tube, m).
  /// @pre 0 <= index < num_targets().
  TargetExposure Evaluate(int index, const View& view, const std::vector<Vec3>& centres) const;

  int num_targets() const { return static_cast<int>(samples_.size()); }
  const std::vector<Vec3>& samples(int index) const { return samples_[static_cast<size_t>(index)]; }
  const mechanics::TargetParams& target(int index) const {
    return targets_[static_cast<size_t>(index)];
  }

 private:
  std::vector<mechanics::TargetParams> targets_;
  std::vector<std::vector<Vec3>> samples_;
  std::vector<double> extent_;  // farthest sample from its target's centre (m)
  double radius_;
};

/// Squared distance between segments [p0, p1] and [q0, q1] (Ericson, Real-Time Collision
/// Detection, 5.1.9).
double SegmentSegmentDistanceSquared(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                     const Vec3& q1);

}  // namespace viscera::assessment
