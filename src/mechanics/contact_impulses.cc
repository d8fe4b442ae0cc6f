#include "mechanics/contact_impulses.h"

#include <algorithm>
#include <cmath>

#include "mechanics/avx_clone.h"

namespace viscera::mechanics {
namespace {

constexpr double kSpeedTolerance = 1e-6;  // m/s: a contact's speed this close to its target is met

// s[j] += change[k] * G(j, column[k]) for every j, k = 0 .. pending - 1 in that order (each
// speed gets the changes in the order they were made). Products and sums only: the AVX clone
// (four speeds at a time) gives the baseline one's numbers bit for bit (avx_clone.h).
VISCERA_AVX_CLONE void AddChanges(double* s, Eigen::Index count, const double* g,
                                  Eigen::Index stride, const Eigen::Index* column,
                                  const double* change, int pending) {
  const double* c0 = g + column[0] * stride;
  switch (pending) {
    case 1:
      for (Eigen::Index j = 0; j < count; ++j) s[j] += change[0] * c0[j];
      break;
    case 2: {
      const double* c1 = g + column[1] * stride;
      for (Eigen::Index j = 0; j < count; ++j)
        s[j] = (s[j] + change[0] * c0[j]) + change[1] * c1[j];
      break;
    }
    case 3: {
      const double* c1 = g + column[1] * stride;
      const double* c2 = g + column[2] * stride;
      for (Eigen::Index j = 0; j < count; ++j)
        s[j] = ((s[j] + change[0] * c0[j]) + change[1] * c1[j]) + change[2] * c2[j];
      break;
    }
    default: {
      const double* c1 = g + column[1] * stride;
      const double* c2 = g + column[2] * stride;
      const double* c3 = g + column[3] * stride;
      for (Eigen::Index j = 0; j < count; ++j) {
        s[j] = (((s[j] + change[0] * c0[j]) + change[1] * c1[j]) + change[2] * c2[j]) +
               change[3] * c3[j];
      }
      break;
    }
  }
}

}  // namespace

int SolveContactImpulses(const MatX& delassus, Eigen::Index count, const VecX& target,
                         double immobile, VecX* lambda, VecX* speed) {
  VecX& l = *lambda;
  double* s = speed->data();
  const double* g = delassus.data();
  const Eigen::Index stride = delassus.outerStride();  // column-major: G(j, i) = g[j + i * stride]
  l.head(count).setZero();
  // Gauss-Seidel: each change adds change * G(:, i) to every speed. Up to kDeferred changes are
  // added to all speeds in one pass (each speed gets them in the order they were made, so it
  // is the same number as one pass per change gives); meanwhile the next contacts' own speeds
  // take the pending changes as they are read. A pass per change read and wrote every speed
  // once per change: ~250 contacts and ~50 sweeps at a pile's landing.
  constexpr int kDeferred = 4;
  Eigen::Index pending_column[kDeferred];
  double pending_change[kDeferred];
  int pending = 0;
  auto flush = [&] {
    AddChanges(s, count, g, stride, pending_column, pending_change, pending);
    pending = 0;
  };
  static_assert(kDeferred == 4, "AddChanges spells out up to four columns");
  for (int sweep = 0; sweep < kMaxContactSweeps; ++sweep) {
    double worst = 0.0;
    for (Eigen::Index i = 0; i < count; ++i) {
      const double gii = g[i + i * stride];
      if (!(gii > immobile)) continue;  // pinned in place: nothing to move
      double si = s[i];
      for (int k = 0; k < pending; ++k) si += pending_change[k] * g[i + pending_column[k] * stride];
      const double next = std::max(0.0, l(i) + (target(i) - si) / gii);
      const double change = next - l(i);
      if (change == 0.0) continue;
      l(i) = next;
      pending_column[pending] = i;
      pending_change[pending] = change;
      if (++pending == kDeferred) flush();
      worst = std::max(worst, std::abs(change) * gii);
    }
    if (pending > 0) flush();
    if (worst < kSpeedTolerance) return sweep + 1;
  }
  return kMaxContactSweeps;
}

}  // namespace viscera::mechanics
