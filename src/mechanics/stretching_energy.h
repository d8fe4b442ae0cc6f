#pragma once
/// The Terzopoulos continuous stretching energy (Terzopoulos et al. 1987; France et al. 2005,
/// section 3.3): E = k/2 ((l / l0)^2 - 1)^2 with l the curve length and l0 the rest length.
/// The paper applies it to the whole curve and differentiates it by finite differences; here
/// the gradient is analytic: l = sum_j sum_g w_g |P_j'(u_g)| (4-point Gauss-Legendre per
/// segment), so dl/dq_{f+a} = sum_g w_g b'_a(u_g) t_g with t_g the unit tangent at node g.
///   Global scope:  one energy over the whole curve (the paper).
///   Segment scope: E = sum_j k_j/2 ((l_j / l0_j)^2 - 1)^2 with k_j = k / #segments, so that
///                  a uniform stretch stores the same energy in both scopes.
#include "mechanics/block_band.h"
#include "mechanics/model.h"

namespace viscera::mechanics {

/// Scratch reused between evaluations.
struct StretchScratch {
  // By node (4 per segment, side by side): the unit tangents' coordinates, the speeds |P'(u_g)|
  // and their inverses (0 where the speed is 0).
  VecX node_tangent_x, node_tangent_y, node_tangent_z;
  VecX node_speed;
  VecX node_inv_speed;
  Points length_gradient;  ///< dl/dq (global scope), #N by 3
  void Resize(int num_points);
};

/// Current curve length (m) with the same quadrature as the energy.
double CurveLength(const Model& model, const Points& q, StretchScratch* scratch);

/// Adds the stretching forces to F and returns the energy (J). With K, adds the banded part of
/// the Hessian; in global scope its dense rank-one part c u u^T is returned through
/// (rank1_u, rank1_coeff) for the solver to apply (Sherman-Morrison) instead of densifying K.
double AddStretchingForces(const Model& model, const Points& q, StretchScratch* scratch, Points* F,
                           BlockBand* K = nullptr, Points* rank1_u = nullptr,
                           double* rank1_coeff = nullptr);

}  // namespace viscera::mechanics
