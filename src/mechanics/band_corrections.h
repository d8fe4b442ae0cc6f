#pragma once
/// The implicit system's low-rank terms beside its band matrix A = M + ĥ D + ĥ² K: the gravity
/// floor's rank-one term w u uᵀ (Sherman-Morrison) and the pins' constraints G dv = 0 (a Schur
/// complement S = G Y, Y = A⁻¹ Gᵀ, factored once per sub-step). Both ride on the band solve:
/// z = A⁻¹ u and Y are solved with the right-hand side, as the columns of one matrix.
#include <Eigen/Dense>

#include "common/types.h"
#include "mechanics/model.h"

namespace viscera::mechanics {

class BandCorrections {
 public:
  explicit BandCorrections(const Model& model);

  /// The columns for the band to solve in place: the right-hand side b (column 0), u (column 1)
  /// and the pins' Gᵀ (3 per pin).
  void Load(const VecX& b, const Points& u);
  /// This sub-step's rank-one weight w (0: none).
  void SetWeight(double w) { w_ = w; }
  MatX& columns() { return columns_; }
  /// The first column after 0 the band must solve: u only with a rank-one term.
  Eigen::Index first_solved() const { return w_ > 0.0 ? 1 : 2; }
  /// After the band solved the columns: Sherman-Morrison's z into Y, and S factored.
  void Prepare(const Points& u);
  /// x (the band system's solution for some right-hand side) <- the solution with the rank-one
  /// term and the pins.
  void Apply(double* x, const Points& u);
  /// w: y += w u uᵀ x is the rank-one term of the exact matrix.
  double weight() const { return w_; }

 private:
  const Model& model_;
  int n_, pins_;
  MatX columns_;  // 3N by (2 + 3 #pins): [b, u, Gᵀ], solved in place
  MatX schur_;    // 3 #pins square
  Eigen::LDLT<MatX> schur_ldlt_;
  VecX pin_rhs_, pin_lambda_;
  double w_ = 0.0;      // h² times the rank-one coefficient, this sub-step
  double denom_ = 1.0;  // 1 + w u.z of Sherman-Morrison
};

}  // namespace viscera::mechanics
