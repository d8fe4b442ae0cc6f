#pragma once
/// The mesentery as a fan of one-sided tethers (docs/mechanics.md, "Mesentery"). Tether k holds
/// curve point P(s_k) to its root point r_k: slack while l = |P(s_k) - r_k| <= L_k, pulling
/// beyond with a force that grows smoothly over the onset d and then like a spring:
///   e = l - L,   g(e) = 0 (e <= 0),  e^2 / (2 d) (0 < e < d),  e - d / 2 (e >= d),
///   F = -k g(e) t,  t = (P - r) / l,   E = k integral g,
/// so the force is C1 in q (no jump in stiffness for the linearized implicit step to miss) and
/// the stiffness k g'(e) t t^T + k g(e) / l (I - t t^T) is positive semi-definite (g >= 0).
/// A taut tether also damps along itself: -c min(e / d, 1) (t . dP/dt) t.
#include <span>

#include "mechanics/block_band.h"
#include "mechanics/model.h"

namespace viscera::mechanics {

/// The pull g(e) of a tether stretched e (m) past its length, per unit stiffness (m), and its
/// slope g'(e). `onset` d >= 0 (0: a plain one-sided spring).
struct TetherPull {
  double g = 0.0;
  double slope = 0.0;
  double energy = 0.0;  ///< integral of g from 0 to e (m^2)
};
TetherPull TetherPullAt(double stretch, double onset);

/// Adds the tethers' generalized forces to F (#N by 3) and returns their energy (J). K and D
/// as in AddSpringForces (each tether touches the 4 control points of its window: within the
/// band). Allocates nothing.
double AddMesenteryForces(std::span<const Tether> tethers, const Points& q, const Points& qd, Points* F,
                          BlockBand* K = nullptr, BlockBand* D = nullptr);

}  // namespace viscera::mechanics
