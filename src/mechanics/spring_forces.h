#pragma once
/// Provot springs between control points (France et al. 2005, section 3.3; Provot 1995):
///   E = 1/2 k (l - l0)^2,  l = |q_i - q_j|,
/// with damping c ((v_j - v_i) . t) t along the spring (t the unit vector from i to j).
#include <span>

#include "mechanics/block_band.h"
#include "mechanics/model.h"

namespace viscera::mechanics {

/// Adds the springs' generalized forces to F (#N by 3) and returns their energy (J).
/// When K / D are given, adds the stiffness -dF/dq (its geometric part clamped to stay
/// positive semi-definite under compression) and the damping -dF/dqd.
double AddSpringForces(std::span<const Spring> springs, const Points& q, const Points& qd,
                       Points* F, BlockBand* K = nullptr, BlockBand* D = nullptr);

}  // namespace viscera::mechanics
