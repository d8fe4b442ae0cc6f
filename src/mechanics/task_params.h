#pragma once
/// The training task a scene sets ([[target]], [assessment]; docs/assessment.md): what the
/// trainee must expose and the thresholds the assessment judges the handling by. Plain data
/// that rides with the model so that every consumer of a scene (session, renderer, replay,
/// viscera-sim) sees it; the mechanics never read it.
#include <optional>
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

/// Running the bowel ([running]; docs/training.md): the bowel is scored in segments of
/// `segment` metres of its rest length, its tissue judged by published injury thresholds, the
/// run by pass marks. Each threshold's default is its source's value.
struct RunningParams {
  double segment = 0.05;         ///< m of the centre line per scored segment (a marker each)
  double jaw_area = 1.0e-4;      ///< m^2 of tissue between the jaws (pressure = grip / area)
  double pinch_force = 10.3;     ///< N of grip that perforates (Heijnsdijk et al. 2003)
  double damage_dose = 300.0;    ///< N s of grip on a segment that damages it (Barrie 2018)
  double traction_break = 14.2;  ///< N of pull that breaks the jejunum (Kratz et al. 2023)
  double camera_range = 0.05;    ///< m: a segment this close in the camera's view is inspected
  double estimate_length = 0.0;  ///< m the trainee is asked to run (0: run it all)
  /// Pass marks (the experts' mean + 1 SD): the run passes when every one is met.
  double pass_coverage = 1.0;         ///< fraction of the segments inspected, at least
  double pass_time = 0.0;             ///< s, at most (0: not judged)
  double pass_path = 0.0;             ///< m of both tools' paths, at most (0: not judged)
  double pass_out_of_view = 0.0;      ///< s a tool was out of view, at most (0: not judged)
  int pass_reversals = 0;             ///< direction reversals, at most
  int pass_slips = 2;                 ///< slips, at most
  int pass_damage_events = 0;         ///< damage events, at most
  double pass_estimate_error = 0.10;  ///< |length error| of the estimation variant, at most
};

struct TaskParams {
  std::vector<TargetParams> targets;
  AssessmentParams assessment;
  std::optional<RunningParams> running;  ///< the scene's [running] task, if any
};

}  // namespace viscera::mechanics
