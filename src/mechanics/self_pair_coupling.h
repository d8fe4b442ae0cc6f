#pragma once
/// The exact coupling of self pairs (docs/self-coupling.md). A self pair couples two windows far
/// apart in the chain, outside the band: the band takes twice the pair's coupling H on each side's
/// own window, which exceeds the exact (J_a - J_b)^T H (J_a - J_b) by the pair's common-mode term
/// (J_a + J_b)^T H (J_a + J_b). This keeps each pair's windows and H (as stiffness and damping)
/// from the last force evaluation and applies that excess at every CG product, so that the
/// integrator removes it and no drag is added; its own class because it is the only part of the
/// contacts the linear solve calls into, many times a sub-step.
#include <vector>

#include "common/check.h"
#include "common/types.h"
#include "mechanics/contact_window.h"

namespace viscera::mechanics {

class SelfPairCoupling {
 public:
  /// Room for `pairs` pairs without allocating.
  explicit SelfPairCoupling(size_t pairs) { pairs_.reserve(pairs); }

  /// A force evaluation starts: no pair yet.
  void Clear() { pairs_.clear(); }
  /// A self pair with windows a and b, k = -dF_a/d(x_a - x_b) and d = -dF_a/d(v_a - v_b).
  void Add(const ContactWindow& a, const ContactWindow& b, const Mat3& k, const Mat3& d) {
    pairs_.push_back({a, b, k, d});
  }
  /// Pairs held (0: the band is exact).
  int size() const { return static_cast<int>(pairs_.size()); }
  /// C_p = ck K_p + cd D_p for each pair, once rather than at each of CG's products.
  void Weigh(double ck, double cd);
  /// y += sum over the pairs of (J_a + J_b)^T C_p (J_a + J_b) x, on 3N values each, ordered
  /// x0 y0 z0 x1 ...
  /// @pre x and y do not overlap (y is added to pair by pair while later pairs still read x).
  void AddCommonModeTerms(const double* x, double* y) const;

 private:
  struct Pair {
    ContactWindow a, b;
    Mat3 k = Mat3::Zero(), d = Mat3::Zero();
    Mat3 weighed = Mat3::Zero();  // ck k + cd d (Weigh)
  };
  std::vector<Pair> pairs_;
};

}  // namespace viscera::mechanics
