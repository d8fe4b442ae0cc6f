#include "mechanics/step.h"

namespace viscera::mechanics {

void Step(const Model& model, const StepInputs& inputs, State* state, Workspace* workspace) {
  const double h = model.substep_size();
  for (int k = 0; k < model.params().substeps; ++k) {
    workspace->integrator().Advance(inputs.loads, h, state);
  }
  ++state->steps;
  state->t = state->steps * model.step_size();  // no drift from summing h
  if (!state->q.allFinite() || !state->qd.allFinite()) {
    state->q = model.params().initial_q;  // same size: no allocation
    state->qd.setZero();
    ++state->nonfinite_resets;
  }
}

}  // namespace viscera::mechanics
