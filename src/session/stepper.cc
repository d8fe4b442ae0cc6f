#include "session/stepper.h"

#include <cmath>

namespace viscera::session {

Stepper::Stepper(const mechanics::Model& model)
    : model_(model),
      workspace_(model),
      state_(mechanics::InitialState(model)),
      last_good_(state_) {}

bool Stepper::Sane(const mechanics::State& s) const {
  if (!s.q.allFinite() || !s.qd.allFinite()) return false;
  // what a step sends: a non-finite tool force is a blow-up too (extreme tool parameters)
  for (const mechanics::ToolState& t : s.tools) {
    if (!t.force.allFinite() || !t.torque.allFinite() || !t.tip.allFinite() ||
        !t.stiffness.allFinite())
      return false;
  }
  if (s.q.rowwise().norm().maxCoeff() > kMaxDistance) return false;
  return s.qd.rowwise().norm().maxCoeff() <= kMaxSpeed;
}

namespace {

// What a restored or reset state keeps of the one it replaces: its time and the counters of the
// whole run, which never go back.
struct RunCounters {
  double t;
  int64_t steps, nonfinite_resets, unconverged_solves;
};

RunCounters CountersOf(const mechanics::State& s) {
  return {s.t, s.steps, s.nonfinite_resets, s.unconverged_solves};
}

void Carry(const RunCounters& c, mechanics::State* s) {
  s->t = c.t;
  s->steps = c.steps;
  s->nonfinite_resets = c.nonfinite_resets;
  s->unconverged_solves = c.unconverged_solves;
}

}  // namespace

bool Stepper::Advance(std::span<const mechanics::ToolTarget> targets) {
  const int64_t resets_before = state_.nonfinite_resets;
  mechanics::Step(model_, mechanics::StepInputs{{}, targets}, &state_, &workspace_);
  // mechanics::Step already replaces a non-finite state by the model's start; a session
  // prefers its last good state, and also catches finite runaways.
  if (state_.nonfinite_resets == resets_before && Sane(state_)) {
    if (state_.steps % kGoodEvery == 0) last_good_ = state_;  // same sizes: no allocation
    return false;
  }
  const RunCounters counters = CountersOf(state_);
  state_ = last_good_;
  Carry(counters, &state_);
  ++recoveries_;
  return true;
}

void Stepper::Reset() {
  const RunCounters counters = CountersOf(state_);
  state_ = mechanics::InitialState(model_);
  Carry(counters, &state_);
  last_good_ = state_;
}

}  // namespace viscera::session
