#pragma once
/// Stepper: the deterministic core of a session, shared by the live mechanics loop and by
/// replay. It steps the model with the given tool targets and guards against blow-ups:
/// a state (tube or tool forces) that is not finite or runs away (points beyond kMaxDistance or
/// faster than kMaxSpeed) is replaced by the last good state, which is saved every kGoodEvery
/// steps. The state's counters (steps, nonfinite_resets, unconverged_solves) carry on through a
/// restore and a Reset: they count the whole run, never go back. Assigning the state restores
/// everything: mechanics::State holds all a step carries over (grasps, CG's warm start, the
/// broad phase's list), so the workspace follows it from the next step on.
/// Same model, same sequence of Advance / Reset calls -> the same states, bit for bit.
#include <cstdint>
#include <span>

#include "mechanics/step.h"

namespace viscera::session {

class Stepper {
 public:
  /// Control points farther than this from the origin mean a runaway (m).
  static constexpr double kMaxDistance = 100.0;
  /// Control point speeds above this mean a runaway (m/s).
  static constexpr double kMaxSpeed = 100.0;
  /// Steps between two saved good states.
  static constexpr int kGoodEvery = 10;

  /// @pre model outlives the stepper.
  explicit Stepper(const mechanics::Model& model);

  /// One mechanics step with these targets (one per model tool, or empty to keep the
  /// previous ones). @return true when the step blew up and the last good state was
  /// restored (its simulated time, step count and counters carry on).
  bool Advance(std::span<const mechanics::ToolTarget> targets);

  /// Back to the model's starting state; time, step count and counters carry on.
  void Reset();

  const mechanics::State& state() const { return state_; }
  const mechanics::Model& model() const { return model_; }
  int64_t recoveries() const { return recoveries_; }

 private:
  bool Sane(const mechanics::State& s) const;

  const mechanics::Model& model_;
  mechanics::Workspace workspace_;
  mechanics::State state_;
  mechanics::State last_good_;
  int64_t recoveries_ = 0;
};

}  // namespace viscera::session
