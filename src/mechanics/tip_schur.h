#pragma once
/// TipSchur: the tools' tips in the tube's implicit solve (docs/tool-coupling.md). Each tip is
/// three more unknowns of the system
///   [A  B] [dv  ]   [b  ]
///   [B' C] [dv_t] = [b_t],   C = m I + h D_tt + h^2 K_tt (3 x 3 per tool),
/// B the tip-tube contacts' and grasps' coupling (Interactions' tip rows and links). The tips are
/// eliminated by a Schur complement: (A - B C^-1 B') dv = b - B C^-1 b_t, then
/// dv_t = C^-1 (b_t - B' dv). B has three columns per tool: the band solve takes them by
/// Woodbury's identity, as it takes the rank-one term and pins. The integrator owns A and its
/// band solve; this class owns B, C, their products and the tips' update.
#include <functional>
#include <vector>

#include "mechanics/band_system_solver.h"
#include "mechanics/interactions.h"

namespace viscera::mechanics {

class TipSchur {
 public:
  /// Solves of one sub-step redone without tip contacts that would pull.
  static constexpr int kMaxRounds = 4;

  TipSchur(int points, int tools, Interactions* interactions);

  /// Whether a sub-step of `state` has tips in the solve.
  bool Present(const State& state) const;
  /// A new sub-step (or half): every tip contact acts again.
  void ClearRounds() { rounds_ = 0; }
  /// K v's rows of the tips, and the links' part of the tube's rows added to `kv`.
  void AddStiffness(const State& state, Points* kv);
  /// The tips' rows for a sub-step of h, and their elimination from the tube's b: b -= B C^-1 b_t.
  void Reduce(double h, VecX* b);
  /// No Woodbury correction until PrepareCorrection (a sub-step without linked tips).
  void Reset() {
    woodbury_ = false;
    linked_ = false;
  }
  /// Y's columns set to B's for the band solve, each with its tool's first linked point (B's
  /// rows are +0 before it) added to `columns` and `first`; a tool with no link gets Y = +0
  /// (its solve's answer) and no column. Nothing without a link.
  void LoadColumns(std::vector<double*>* columns, std::vector<int>* first);
  /// Once the band has solved those columns (Y = P^-1 B): `corrections` on each (the
  /// preconditioner's rank-one and pins' terms, called while this correction is still off), and
  /// S = C - B' Y.
  void PrepareCorrection(const std::function<void(double*)>& corrections);
  /// Whether PrepareCorrection made a correction (some tip is linked to the tube).
  bool woodbury() const { return woodbury_; }
  /// x (3N, a band solution) <- that of P - B C^-1 B': x += Y S^-1 Y' x.
  void ApplyCorrection(double* x) const;
  /// y -= B C^-1 B' x (the exact matrix's tip term).
  void SubtractSchur(const double* x, double* y) const;
  /// dv_t for the tube's dv; true when a tip contact would pull at the end and was released, or
  /// was stiffened (the sub-step is then solved again, at most kMaxRounds times).
  bool Solve(double h, const Points& v, const double* dv, const State& state);
  /// Counts a solve done again for the tips.
  void CountRound() { ++rounds_; }
  /// The tips' change of velocity from the last Solve (3 per tool).
  const VecX& dv() const { return dv_; }
  /// Moves the tips by the last Solve, and by -C^-1 B' of the depth constraints' correction
  /// (h times `depth_dq`, when not null).
  void Advance(double h, const VecX* depth_dq, State* state);

 private:
  // *out = B' x and y -= B z, on the rows of B that are not +0 (row_begin_, row_end_).
  void TransposedProduct(const double* x, VecX* out) const;
  void SubtractProduct(const VecX& z, double* y) const;

  int n_;  // control points
  int num_tools_;
  Interactions* interactions_;
  // B (3N by 3T), Y = P^-1 B, C and C^-1 (block diagonal), S = C - B' Y, the tips' right-hand
  // side and K v rows, scratch of 3T.
  bool linked_ = false, woodbury_ = false;
  MatX B_, Y_, c_, c_inv_, S_;
  std::vector<int> first_;           // per tool: its first linked point (n_: none)
  int row_begin_ = 0, row_end_ = 0;  // B's rows that may not be +0 (Reduce)
  Eigen::LDLT<MatX> S_ldlt_;
  VecX b_, kv_, dv_, v_;
  mutable VecX tmp_, tmp2_;
  int rounds_ = 0;  // solves of this sub-step redone without pulling tip contacts
};

}  // namespace viscera::mechanics
