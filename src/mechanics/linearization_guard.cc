#include "mechanics/linearization_guard.h"

#include <algorithm>
#include <limits>

namespace viscera::mechanics {
namespace {

// Segment e = q_i+1 - q_i of the control polygon, moved by Δe = dq_i+1 - dq_i. With l² = |e|² and
// p = e·Δe, a = l + p / l is its first-order length and |Δe_⊥|² = |Δe|² - p² / l², so its
// unseen stretch |Δe_⊥|² / 2a, as a fraction of l, is sideways / (2 l² first_order), both
// scaled by l² (first_order = a l): no root and no division.
struct SegmentMotion {
  double l2;           // |e|²
  double first_order;  // l² + p: its first-order length times l (<= 0: turned inside out)
  double sideways;     // |Δe_⊥|² l²
};

SegmentMotion Motion(const Points& q, const Points& dq, Eigen::Index i) {
  const Vec3 e = (q.row(i + 1) - q.row(i)).transpose();
  const Vec3 de = (dq.row(i + 1) - dq.row(i)).transpose();
  const double l2 = e.squaredNorm(), p = e.dot(de);
  return {l2, l2 + p, de.squaredNorm() * l2 - p * p};
}

}  // namespace

bool LinearizationGuard::UnseenStretchWithin(const Points& q, const Points& dq, double limit) {
  // Branch-free: the loop vectorizes, and a whole pass costs ~0.4 µs on the cavity's 190 points.
  bool within = true;
  for (Eigen::Index i = 0; i + 1 < q.rows(); ++i) {
    const SegmentMotion m = Motion(q, dq, i);
    within &=
        (m.first_order > 0.0 || m.l2 == 0.0) & (m.sideways <= 2.0 * limit * m.l2 * m.first_order);
  }
  return within;
}

double LinearizationGuard::UnseenStretch(const Points& q, const Points& dq) {
  double largest = 0.0;
  for (Eigen::Index i = 0; i + 1 < q.rows(); ++i) {
    const SegmentMotion m = Motion(q, dq, i);
    if (m.l2 == 0.0) continue;
    if (!(m.first_order > 0.0)) return std::numeric_limits<double>::infinity();
    largest = std::max(largest, m.sideways / (2.0 * m.l2 * m.first_order));
  }
  return largest;
}

}  // namespace viscera::mechanics
