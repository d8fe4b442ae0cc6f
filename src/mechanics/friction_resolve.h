#pragma once
/// FrictionResolve: a sub-step's solve done again for contacts whose stick or slip a revision
/// changed (Interactions::ReviseFriction), without evaluating the sub-step again. Only the revised
/// pairs' terms differ from the evaluation (StickSlipFriction::Change): b takes their change of F
/// and K, the exact matrix their change of K and D, and CG starts from the last solve's dv with
/// the preconditioner as it was. The integrator owns b, the system and CG; this class owns the
/// revised pairs and what the evaluation made, and sees the system only through its band solve.
#include <cstdint>
#include <functional>
#include <vector>

#include "mechanics/interactions.h"
#include "mechanics/stick_slip_friction.h"

namespace viscera::mechanics {

class FrictionResolve {
 public:
  /// `band_inverse(x)`: x <- the band system's solution for x (with its rank-one term and pins),
  /// the preconditioner of the sub-step's CG. With `stick_slip`, room for the revised pairs is
  /// reserved here, so that a step allocates nothing.
  FrictionResolve(int points, Interactions* interactions, bool stick_slip,
                  std::function<void(double*)> band_inverse);

  /// A new evaluation of the sub-step: no pair revised, the exact matrix as it made it.
  void Clear() {
    changed_ = false;
    changes_.clear();
  }
  /// After Interactions::ReviseFriction: b (the right-hand side, as the evaluation made it the
  /// first time) takes the revised pairs' changes, dv the band's answer to it, and the state's CG
  /// correction the rest of the last solve's dv, from which CG goes on. The weights are the
  /// scheme's (ImplicitEulerIntegrator::StepWeights): ĥ, ĥ² and μ. False, changing neither b nor
  /// dv, when a tool's pair changed (the sub-step is then evaluated again).
  bool TakeRevisions(double h_eff, double stiffness, double history, VecX* b, Eigen::Ref<VecX> dv,
                     State* state);
  /// y += the revised pairs' terms of the exact matrix (ĥ² K + ĥ D), for x (3N values); nothing
  /// before TakeRevisions.
  void AddTerms(const double* x, double* y) const {
    if (!changed_) return;
    for (const StickSlipFriction::Change& c : changes_) {
      const Vec3 r = c.Motion(x);
      c.Scatter(stiffness_ * (c.k * r) + damping_ * (c.d * r), y);
    }
  }

  /// Whether revised contacts are solved again this way (on by default; off, the sub-step is
  /// evaluated again: to compare the two, in tests).
  bool enabled() const { return enabled_; }
  void set_enabled(bool on) { enabled_ = on; }
  /// Solves done again this way.
  int64_t resolves() const { return resolves_; }

 private:
  Interactions* interactions_;
  std::function<void(double*)> band_inverse_;
  // The revised pairs of this evaluation, b as the evaluation made it, the last solve's dv, and
  // the weights of the pairs' K and D in the exact matrix.
  std::vector<StickSlipFriction::Change> changes_;
  VecX b_evaluated_, dv_solved_;
  bool changed_ = false;
  double stiffness_ = 0.0, damping_ = 0.0;
  bool enabled_ = true;
  int64_t resolves_ = 0;
};

}  // namespace viscera::mechanics
