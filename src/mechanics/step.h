#pragma once
/// One step of the mechanical layer: `substeps` integrator sub-steps of h = 1 / (rate_hz *
/// substeps). The Workspace belongs to the stepping thread; Step allocates nothing in steady
/// state (tests/mechanics/step_test.cc checks it).
#include <memory>
#include <span>

#include "mechanics/integrator.h"
#include "mechanics/interactions.h"

namespace viscera::mechanics {

/// What the world feeds a step. Contacts and tools extend this.
struct StepInputs {
  std::span<const PointLoad> loads;  ///< external forces, held for the whole step
  /// Device targets, one per model tool in scene order; empty keeps the previous targets.
  std::span<const ToolTarget> tools;
};

/// Scratch owned by the thread that steps one simulation. Non-copyable.
class Workspace {
 public:
  /// @pre model outlives the workspace.
  explicit Workspace(const Model& model)
      : interactions_(Interactions::Needed(model) ? std::make_unique<Interactions>(model)
                                                  : nullptr),
        integrator_(MakeIntegrator(model, interactions_.get())) {}
  Workspace(const Workspace&) = delete;
  Workspace& operator=(const Workspace&) = delete;
  Integrator& integrator() { return *integrator_; }
  /// Contacts and tools; null when the model has neither.
  Interactions* interactions() { return interactions_.get(); }

 private:
  std::unique_ptr<Interactions> interactions_;
  std::unique_ptr<Integrator> integrator_;
};

/// Advances state by one step (1 / rate_hz seconds). Each sub-step re-places the sphere chain,
/// moves the tools and finds contacts before the integrator runs. A step whose result is not
/// finite resets the state to the model's start (t and the counters continue) and counts it in
/// state->nonfinite_resets, so a session survives a blow-up instead of propagating NaN. The step
/// reads nothing of the workspace's past: from the same state, it is the same whatever the
/// workspace stepped before (State holds all that carries over).
void Step(const Model& model, const StepInputs& inputs, State* state, Workspace* workspace);

}  // namespace viscera::mechanics
