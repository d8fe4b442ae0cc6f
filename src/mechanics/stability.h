#pragma once
/// Explicit-integration stability. RK4's stability region reaches about 2.8 along the imaginary
/// axis and 2.785 along the negative real axis, so a step h is stable while h * rho < 2.8, rho
/// being the largest rate of the linearized system: an undamped mode of frequency omega has
/// rate omega; a damping rate delta adds delta/2 + sqrt(delta^2/4 + omega^2) - omega at worst.
#include "mechanics/model.h"
#include "mechanics/state.h"

namespace viscera::mechanics {

inline constexpr double kRk4StabilityLimit = 2.8;

struct StabilityEstimate {
  double omega_max = 0.0;     ///< sqrt(lambda_max(M^-1 K)) (rad/s)
  double damping_max = 0.0;   ///< lambda_max(M^-1 D) (1/s)
  double rate_max = 0.0;      ///< delta/2 + sqrt(delta^2/4 + omega^2) (1/s)
  double h_times_rate = 0.0;  ///< for the model's sub-step
  int stable_substeps = 1;    ///< smallest sub-step count with h * rate_max < 2.8
  bool stable() const { return h_times_rate < kRk4StabilityLimit; }
};

/// Lanczos on the forces' linearization at `state` (allocates; call at load time).
StabilityEstimate EstimateStability(const Model& model, const State& state);

}  // namespace viscera::mechanics
