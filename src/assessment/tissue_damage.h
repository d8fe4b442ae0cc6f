#pragma once
/// The tissue-damage model of running the bowel (docs/training.md): the jaws' grip on the
/// segment they hold, its pressure over the jaw area, grip x time accumulated per segment, and
/// the pull on the bowel, each judged by a published injury threshold (RunningParams). Fed one
/// tool state at a time; allocation-free after construction.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "assessment/report.h"
#include "mechanics/task_params.h"

namespace viscera::assessment {

/// Damage kinds, as bits of a segment's flags.
enum DamageKind : uint8_t { kPinch = 1, kDose = 2, kTraction = 4 };

class TissueDamage {
 public:
  /// @param length the bowel's rest length (m); the segments are its `p.segment` long pieces.
  TissueDamage(const mechanics::RunningParams& p, double length, std::vector<std::string> tools);

  /// One step of `dt` s ending at `t` of tool `tool`: while `grasping`, the jaws grip the bowel
  /// at curve parameter s (0..1 along its rest length) with `grip` N and pull it with `pull` N.
  void Add(int tool, bool grasping, double s, double grip, double pull, double t, double dt);

  int segments() const { return static_cast<int>(dose_.size()); }
  /// The segment holding curve parameter s (0..1).
  int SegmentOf(double s) const;
  /// Per segment: grip x time so far (N s) and the DamageKind bits of its events.
  const std::vector<double>& dose() const { return dose_; }
  const std::vector<uint8_t>& flags() const { return flags_; }
  const std::vector<DamageEvent>& events() const { return events_; }
  double max_grip() const { return max_grip_; }
  double max_traction() const { return max_traction_; }
  double max_dose() const;
  /// The segments with a damage event as ranges [from, to] of the curve parameter s (0..1),
  /// neighbours merged: what the frames draw in the damage colour.
  std::vector<std::pair<double, double>> DamagedRanges() const;

 private:
  struct Tool {
    bool pinched = false;  // this grasp already made a pinch event
    bool pulled = false;   // this excursion above the breaking force already made an event
  };
  void Event(DamageKind kind, int segment, int tool, double t, double value);

  mechanics::RunningParams p_;
  double length_;
  std::vector<std::string> names_;
  std::vector<Tool> tools_;
  std::vector<double> dose_;
  std::vector<uint8_t> flags_;
  std::vector<DamageEvent> events_;
  double max_grip_ = 0.0, max_traction_ = 0.0;
};

}  // namespace viscera::assessment
