#pragma once
/// Soft attachments: a spring from curve point P(s) to a fixed anchor,
///   E = 1/2 k (|P(s) - a| - r)^2,
/// plus viscous damping -c dP(s)/dt; both mapped to generalized forces through b_i(s).
/// They model the anatomy: both ends of the small intestine are held (duodenojejunal flexure,
/// ileocecal junction) and the mesentery holds it loosely toward its root.
#include <span>

#include "mechanics/block_band.h"
#include "mechanics/model.h"

namespace viscera::mechanics {

/// Adds w_a w_b h to the blocks (first + a, first + b) of m: the Hessian of a function of the
/// curve point P(s) = sum_a w_a q_a whose Hessian in P is h (3 x 3).
void AddCurvePointOuter(const CurvePoint& at, const Mat3& h, BlockBand* m);

/// Adds forces to F (#N by 3); returns the energy (J). K and D as in AddSpringForces.
double AddAttachmentForces(std::span<const Attachment> attachments, const Points& q,
                           const Points& qd, Points* F, BlockBand* K = nullptr,
                           BlockBand* D = nullptr);

}  // namespace viscera::mechanics
