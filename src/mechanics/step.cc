#include "mechanics/step.h"

#include <utility>

namespace viscera::mechanics {

void Step(const Model& model, const StepInputs& inputs, State* state, Workspace* workspace) {
  Interactions* interactions = workspace->interactions();
  // Impacts get more sub-steps (never fewer than the scene asks for).
  const int substeps =
      interactions ? interactions->RequiredSubsteps(state) : model.params().substeps;
  const double h = model.step_size() / substeps;
  for (int k = 0; k < substeps; ++k) {
    if (interactions)
      interactions->BeginSubstep(k == 0 ? inputs.tools : std::span<const ToolTarget>{}, h, state);
    workspace->integrator().Advance(inputs.loads, h, state);
  }
  state->substeps = substeps;
  ++state->steps;
  state->t = state->steps * model.step_size();  // no drift from summing h
  if (!state->q.allFinite() || !state->qd.allFinite()) {
    // The whole state back to the start (its grasps, warm start and broad phase too: nothing of
    // the blown-up step carries on); the time and the run's counters go on.
    State start = InitialState(model);  // allocates, but only on this error path
    start.t = state->t;
    start.steps = state->steps;
    start.substeps = state->substeps;
    start.nonfinite_resets = state->nonfinite_resets + 1;
    start.unconverged_solves = state->unconverged_solves;
    *state = std::move(start);
  }
  if (interactions) interactions->EndStep(state);
}

}  // namespace viscera::mechanics
