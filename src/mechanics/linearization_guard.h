#pragma once
/// The implicit step's linearization guard (docs/integrators.md, "One linearization per
/// sub-step"): a sub-step is one linearization of the forces, and a segment of the control
/// polygon turned far within it stretches by what the linear model cannot see (a slack tube
/// pulled sideways has no sideways stiffness to first order); that stretch returns as energy
/// nobody put in. The guard measures it on the sub-step's motion and decides whether the
/// sub-step is done again as two halves. Its own unit because it is pure geometry on (q, dq),
/// tested alone, and read by nothing of the solve.
#include "common/types.h"

namespace viscera::mechanics {

class LinearizationGuard {
 public:
  /// The largest stretch a sub-step may leave unseen by its linearization, as a fraction of a
  /// segment of the control polygon (UnseenStretchWithin); a sub-step past it is done again as
  /// two halves, and a half again only while halving at least halves it (Halve).
  static constexpr double kMaxUnseenStretch = 0.05;
  /// The same for a BDF2 sub-step, which would give the unseen stretch back as energy; past it
  /// the sub-step is backward Euler. A tenth of the halving's limit: at 0.01 a 40 cm hairpin
  /// snapping straight still gained 0.2 % of its energy in a step at 1 kHz, at 0.005 none of the
  /// hairpins at 100-1000 Hz gains; a swinging loop stays far below it.
  static constexpr double kMaxUnseenStretchBdf2 = 0.005;

  /// Whether, for every segment e = q_i+1 - q_i of the control polygon moved by dq, the stretch
  /// the step's single linearization cannot see, |Δe_⊥|² / 2 (|e| + ê·Δe) (the sideways motion's
  /// second-order lengthening over the first-order length; sin²θ / 2 cos θ ≈ θ²/2 of |e| for a
  /// segment turned by θ), is at most `limit` |e|, and no segment is turned inside out
  /// (|e| + ê·Δe <= 0). Coincident points are skipped.
  static bool UnseenStretchWithin(const Points& q, const Points& dq, double limit);
  /// The largest of that unseen stretch over the segments, as a fraction of each (infinite if a
  /// segment turns inside out): what a halving must at least halve to be tried again.
  static double UnseenStretch(const Points& q, const Points& dq);
  /// 0 when the motion dq from q is within kMaxUnseenStretch, else its UnseenStretch.
  static double Excess(const Points& q, const Points& dq) {
    return UnseenStretchWithin(q, dq, kMaxUnseenStretch) ? 0.0 : UnseenStretch(q, dq);
  }
  /// Whether a sub-step of that excess (Excess), at depth `halvings`, is done again as two
  /// halves: at the top whenever it has any, and below only while halving at least halved its
  /// parent's (parent_excess); what halving does not shrink (a position correction, a speed the
  /// step length does not set) it cannot mend, and is accepted as the plain step would be.
  static bool Halve(double excess, int halvings, double parent_excess) {
    return excess > 0.0 && (halvings == 0 || excess < 0.5 * parent_excess);
  }
};

}  // namespace viscera::mechanics
