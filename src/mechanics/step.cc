#include "mechanics/step.h"

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
    state->q = model.params().initial_q;  // same size: no allocation
    state->qd.setZero();
    state->last_h = 0.0;                      // nothing for a BDF2 step to build on
    const State start = InitialState(model);  // allocates, but only on this error path
    state->tools = start.tools;
    state->friction.clear();
    ++state->nonfinite_resets;
  }
  if (interactions) interactions->EndStep(state);
}

}  // namespace viscera::mechanics
