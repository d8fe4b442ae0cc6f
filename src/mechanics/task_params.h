#pragma once
/// The training task a scene sets ([[target]], [assessment]; docs/assessment.md): what the
/// trainee must expose and the thresholds the assessment judges the handling by. Plain data
/// that rides with the model so that every consumer of a scene (session, renderer, replay,
/// viscera-sim) sees it; the mechanics never read it.
#include <string>
#include <vector>

#include "common/types.h"

namespace viscera::mechanics {

/// A patch to expose (a lesion on the posterior wall or an organ): a disc (centre, normal,
/// radius) or a planar polygon, and how many points sample it.
struct TargetParams {
  std::string name;
  Vec3 centre = Vec3::Zero();   ///< m; for a polygon, the mean of its corners
  Vec3 normal = Vec3::UnitZ();  ///< unit, toward where it can be seen from
  double radius = 0.0;          ///< disc radius (m); 0 for a polygon
  std::vector<Vec3> polygon;    ///< corners (m), coplanar, in order; empty for a disc
  int samples = 64;             ///< sample points (their visible fraction is the exposure)
};

/// Thresholds and rates of the assessment ([assessment]); docs/assessment.md says where the
/// defaults come from.
struct AssessmentParams {
  double traction_force = 3.0;     ///< N on the tissue: above it, tissue-damage range
  double traction_hold = 0.5;      ///< s above traction_force that make one traction event
  double regrasp_window = 1.0;     ///< s: a grasp this soon after a release is a regrasp
  double exposed_fraction = 0.9;   ///< exposure at which a target counts as exposed
  double exposure_rate_hz = 10.0;  ///< exposure evaluations per second (server)
};

struct TaskParams {
  std::vector<TargetParams> targets;
  AssessmentParams assessment;
};

}  // namespace viscera::mechanics
