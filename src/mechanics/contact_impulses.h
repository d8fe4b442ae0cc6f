#pragma once
/// Inelastic contact impulses on a Delassus matrix: the small linear complementarity problem
/// shared by the impact limiter (through the mass matrix) and the implicit step's impact
/// constraints (through its system matrix).
#include "common/types.h"

namespace viscera::mechanics {

/// Projected Gauss-Seidel (Jean & Moreau; Erleben 2007): finds impulses λ ≥ 0 such that every
/// contact's normal speed s = s0 + G λ reaches at least its target, with λ_i = 0 where contact i
/// needs none (complementarity: never a pull, never more than the target asks).
/// @param delassus   at least count by count, symmetric positive semidefinite: G = J W J^T, the
///                   normal speed of contact i per unit impulse on contact j (W: the inverse
///                   of the matrix the impulses act through)
/// @param target     count: the least normal speed each contact may keep (m/s, ≤ 0)
/// @param immobile   a contact with G_ii at most this is pinned in place: left alone
/// @param lambda     count: the impulses (N s), solved from zero
/// @param speed      count: s0 on entry, s at the returned λ
/// @return the sweeps used (at most kMaxContactSweeps)
int SolveContactImpulses(const MatX& delassus, Eigen::Index count, const VecX& target,
                         double immobile, VecX* lambda, VecX* speed);
constexpr int kMaxContactSweeps = 100;

}  // namespace viscera::mechanics
