#pragma once
/// The mesentery as a fan of one-sided tethers (docs/mechanics.md, "Mesentery"). Tether k holds
/// curve point P(s_k) to its root point r_k: slack while l = |P(s_k) - r_k| <= L_k, pulling
/// beyond with a force that stiffens with the stretch, J-shaped like collagen:
///   e = l - L,   g(e) = 0 (e <= 0),  e^3 / (3 d^2) (0 < e <= 2 d),  8 d / 3 + 4 (e - 2 d) beyond,
///   F = -k g(e) t,  t = (P - r) / l,   E = k integral g,   d the onset,
/// so the force is C1 in q (no jump in stiffness for the linearized implicit step to miss), soft
/// while barely taut (a resting pile does not press loops together), stiff under a pull (k at
/// e = d, 4 k from 2 d on) and never stiffer than 4 k (a tether far past its slack, as in a
/// scene's starting pose, pulls hard but linearly). The stiffness k g'(e) t t^T + k g(e) / l (I - t
/// t^T) is positive semi-definite (g >= 0). A taut tether also damps along itself: -c min(e / d, 1)
/// (t . dP/dt) t. d = 0 makes a plain one-sided spring (g = e).
#include <span>

#include "mechanics/block_band.h"
#include "mechanics/model.h"

namespace viscera::mechanics {

/// The pull g(e) of a tether stretched e (m) past its length, per unit stiffness (m), its slope
/// g'(e) and its integral (m^2). `onset` d >= 0 (0: a plain one-sided spring).
struct TetherPull {
  double g = 0.0;
  double slope = 0.0;
  double energy = 0.0;  ///< integral of g from 0 to e (m^2)
};
TetherPull TetherPullAt(double stretch, double onset);

/// Adds the tethers' generalized forces to F (#N by 3) and returns their energy (J). K and D
/// as in AddSpringForces (each tether touches the 4 control points of its window: within the
/// band). Allocates nothing.
double AddMesenteryForces(std::span<const Tether> tethers, const Points& q, const Points& qd,
                          Points* F, BlockBand* K = nullptr, BlockBand* D = nullptr);

}  // namespace viscera::mechanics
