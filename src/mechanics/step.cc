#include "mechanics/step.h"

namespace viscera::mechanics {

void Step(const Model& model, const StepInputs& inputs, State* state, Workspace* workspace) {
  const double h = model.substep_size();
  Interactions* interactions = workspace->interactions();
  for (int k = 0; k < model.params().substeps; ++k) {
    if (interactions) interactions->BeginSubstep(k == 0 ? inputs.tools : std::span<const ToolTarget>{}, h, state);
    workspace->integrator().Advance(inputs.loads, h, state);
  }
  ++state->steps;
  state->t = state->steps * model.step_size();  // no drift from summing h
  if (!state->q.allFinite() || !state->qd.allFinite()) {
    state->q = model.params().initial_q;  // same size: no allocation
    state->qd.setZero();
    for (ToolState& tool : state->tools) tool = ToolState{};
    ++state->nonfinite_resets;
  }
  if (interactions) interactions->EndStep(state);
}

}  // namespace viscera::mechanics
