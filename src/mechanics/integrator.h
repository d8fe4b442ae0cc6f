#pragma once
/// One interface for the time integrators; the scene picks one ([simulation] integrator).
#include <memory>
#include <span>

#include "mechanics/forces.h"
#include "mechanics/state.h"

namespace viscera::mechanics {

class Integrator {
 public:
  virtual ~Integrator() = default;
  /// Advances state->q and state->qd by h seconds (does not touch state->t).
  /// Allocates nothing in steady state.
  virtual void Advance(std::span<const PointLoad> loads, double h, State* state) = 0;
};

/// The integrator the model asks for, with its own scratch. The model (and `interactions`, which
/// may be null) must outlive it.
std::unique_ptr<Integrator> MakeIntegrator(const Model& model,
                                           Interactions* interactions = nullptr);

}  // namespace viscera::mechanics
