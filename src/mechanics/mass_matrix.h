#pragma once
/// The Lagrangian mass matrix of a dynamic spline (Remion et al. 1999; France et al. 2005,
/// section 3.4): M_ij = m * integral_0^1 b_i(s) b_j(s) ds, with m the total mass spread
/// uniformly along the rest curve. Every segment adds the same Gram block of its window
/// (scaled by m / #segments), integrated exactly by 4-point Gauss-Legendre (degree 6).
#include "mechanics/banded_cholesky.h"
#include "spline/catmull_rom.h"

namespace viscera::mechanics {

/// Upper band (#N by 4) of M for a chain of `curve.num_points()` control points.
Band BuildMassBand(const spline::CatmullRom& curve, double mass);

/// Row sums of M (#N): m * integral b_i ds, the share of the mass that gravity pulls on q_i.
VecX MassRowSums(const Band& band);

}  // namespace viscera::mechanics
