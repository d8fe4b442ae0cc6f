#pragma once
/// The scoring of running the bowel (docs/training.md): which 5 cm segments were inspected
/// (grasped between the jaws, or seen by the camera at close range), in what order, how the
/// tools were handled, and the tissue damage; judged by the scene's pass marks. Fed with the
/// state each step leaves, like SessionMetrics (which owns one when the scene has [running]).
#include <optional>
#include <vector>

#include "assessment/exposure.h"
#include "assessment/report.h"
#include "assessment/tissue_damage.h"
#include "mechanics/model_params.h"
#include "mechanics/state.h"

namespace viscera::assessment {

class RunningScore {
 public:
  /// @pre params.task.running is set; `params` outlives this.
  explicit RunningScore(const mechanics::ModelParams& params);

  /// The camera the trainee sees through (none: no camera coverage, no time out of view).
  void SetView(const View& view) { view_ = view; }
  /// Takes the state one step of `dt` s left.
  void AddStep(const mechanics::State& state, double dt);
  void Fill(RunningReport* report) const;

  const TissueDamage& damage() const { return damage_; }
  const std::vector<char>& covered() const { return covered_; }

 private:
  struct Tool {
    bool grasping = false;
    bool had_tip = false;
    Vec3 last_tip = Vec3::Zero();
    double last_grasp_s = -1.0;  // where this tool last grasped (curve parameter)
    int64_t slips = 0;
  };
  void Grasped(int tool, double s);
  bool InView(const Vec3& p) const;
  void CameraCoverage(const Points& q);

  const mechanics::ModelParams& params_;
  const mechanics::RunningParams& p_;
  TissueDamage damage_;
  std::optional<View> view_;
  std::vector<Tool> tools_;
  std::vector<char> covered_;
  double time_ = 0.0, first_grasp_ = -1.0, last_grasp_end_ = -1.0;
  double path_ = 0.0, out_of_view_ = 0.0;
  int64_t grasps_ = 0, regrasps_ = 0;
  int reversals_ = 0, direction_ = 0;  // direction: +1 toward the ileocecal end, -1 back, 0 none
  double last_s_ = -1.0;               // the last grasp of either tool
  double first_s_ = -1.0;
  bool clashing_ = false;
  int64_t clashes_ = 0;
};

}  // namespace viscera::assessment
