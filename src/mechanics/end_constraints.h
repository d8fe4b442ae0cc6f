#pragma once
/// EndConstraints: the impacts and depth constraints an implicit sub-step holds inside its solve
/// (docs/impacts.md). Impulses J^T Λ act through the implicit system A = M + h D + h^2 K rather
/// than through M alone, so the tube's stretching stiffness spreads a stopped sphere's correction
/// along the chain: for the pairs that v + dv would still leave too deep, dv += A^-1 J^T Λ with
/// Λ ≥ 0 the least impulses that bring them within their bound (impacts), then a position
/// correction that gives no pair a separating speed (depth). The integrator owns the system;
/// this class sees it only through its band solve.
#include <cstdint>
#include <functional>
#include <vector>

#include "mechanics/impact_limiter.h"
#include "mechanics/incremental_delassus.h"
#include "mechanics/interactions.h"
#include "mechanics/model.h"

namespace viscera::mechanics {

class EndConstraints {
 public:
  /// `band_inverse(x)`: x <- the band system's solution for x (with its rank-one term and pins),
  /// the one the sub-step's solve was preconditioned with.
  EndConstraints(const Model& model, Interactions* interactions,
                 std::function<void(double*)> band_inverse);

  /// Whether a sub-step that moves q by `dq` would need impact or depth constraints.
  bool Needed(double h, const Points& dq);
  /// After the solve: dv += the impacts' A^-1 J^T Λ for velocity v + dv. Returns whether q also
  /// needs depth_dq() (h times it) on top of h (v + dv).
  bool Resolve(double h, const Points& v, Eigen::Ref<VecX> dv);
  /// The depth constraints' correction of the last Resolve that returned true (3N, a velocity).
  const VecX& depth_dq() const { return depth_dq_; }

  /// Whether impulses and depth corrections between parts of a free tube are kept from the
  /// momentum that the band system they act through gives them (KeepPairsMomentum). On by
  /// default; off only to show it is needed, in tests.
  void set_momentum_kept(bool on) { momentum_kept_ = on; }
  /// Sub-steps whose solve needed impulses, and those impulses' contacts in all.
  int64_t substeps() const { return substeps_; }
  int64_t contacts() const { return contacts_total_; }

 private:
  // One kind of end constraint on the velocity `base`: *delta = A^-1 J^T Λ (3N), or returns false
  // when no pair needs one.
  bool Solve(Interactions::EndConstraint kind, double h, const Points& base, VecX* delta);
  // delta (3N, from Solve on self pairs) less the momentum the band's excess on the pairs'
  // common motion gave it.
  void KeepPairsMomentum(double h, VecX* delta);
  // x (3N) <- J_i x, the normal speed of contact i.
  double ContactSpeed(const ImpactLimiter::Contact& c, const double* x) const;

  const Model& model_;
  Interactions* interactions_;
  int n_;  // control points
  std::function<void(double*)> band_inverse_;
  // The contacts, A^-1 J_i^T per contact (3N by contacts, through the band system), their
  // Delassus matrix and impulses.
  std::vector<ImpactLimiter::Contact> set_;
  MatX columns_;
  IncrementalDelassus<ImpactLimiter::Contact> delassus_;
  VecX lambda_, speed_, target_, impact_dv_, depth_dq_;
  Points v_, check_;
  int64_t substeps_ = 0, contacts_total_ = 0;
  bool momentum_kept_ = true;
};

}  // namespace viscera::mechanics
