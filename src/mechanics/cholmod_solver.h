#pragma once
/// SuiteSparse CHOLMOD behind a small RAII interface: a sparse SPD matrix with a fixed
/// pattern, analysed once (fill-reducing ordering and symbolic factor), numerically
/// refactored whenever its values change, and solved with reusable workspace so that the
/// steady state allocates nothing.
#include <cholmod.h>

#include <vector>

#include "common/types.h"

namespace viscera::mechanics {

/// Owns a cholmod_common. Non-copyable; one per thread that uses CHOLMOD.
class CholmodCommon {
 public:
  CholmodCommon();
  ~CholmodCommon();
  CholmodCommon(const CholmodCommon&) = delete;
  CholmodCommon& operator=(const CholmodCommon&) = delete;
  cholmod_common* get() { return &common_; }

 private:
  cholmod_common common_;
};

/// Solve-side workspace that cholmod_solve2 reuses between calls of the same width.
class CholmodSolveWorkspace {
 public:
  explicit CholmodSolveWorkspace(CholmodCommon* common) : common_(common) {}
  ~CholmodSolveWorkspace();
  CholmodSolveWorkspace(const CholmodSolveWorkspace&) = delete;
  CholmodSolveWorkspace& operator=(const CholmodSolveWorkspace&) = delete;

 private:
  friend class CholmodSolver;
  CholmodCommon* common_;
  cholmod_dense* x_ = nullptr;
  cholmod_dense* y_ = nullptr;
  cholmod_dense* e_ = nullptr;
};

/// A symmetric positive definite matrix stored as its upper triangle in compressed columns.
class CholmodSolver {
 public:
  enum class Kind { kAuto, kSimplicial, kSupernodal };

  explicit CholmodSolver(CholmodCommon* common, Kind kind = Kind::kAuto);
  ~CholmodSolver();
  CholmodSolver(const CholmodSolver&) = delete;
  CholmodSolver& operator=(const CholmodSolver&) = delete;

  /// Sets the pattern (upper triangle, rows sorted within each column) and runs the symbolic
  /// analysis. Values are zero until written through values().
  /// @pre col_ptr has n + 1 entries; row_index has col_ptr[n] entries, each <= its column.
  void SetPattern(int n, const std::vector<int>& col_ptr, const std::vector<int>& row_index);

  /// Numeric values in pattern order (col_ptr[n] of them).
  double* values();
  int size() const { return n_; }

  /// Numeric factorization with the analysed pattern. Returns false when the matrix is not
  /// positive definite (the factor is then unusable).
  bool Factorize();

  /// Solves A X = B for `num_columns` column-major right-hand sides (#n by num_columns),
  /// writing X over `b`. Allocates nothing once `work` has served this width.
  void SolveInPlace(double* b, int num_columns, CholmodSolveWorkspace* work);

 private:
  CholmodCommon* common_;
  Kind kind_;
  int n_ = 0;
  cholmod_sparse* a_ = nullptr;
  cholmod_factor* factor_ = nullptr;
};

/// The mass matrix through CHOLMOD (the alternative to BandedCholesky; see the benchmark).
class CholmodBandSolver {
 public:
  CholmodBandSolver();
  /// @throws InputError when the band matrix is not positive definite.
  void Factor(const Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>& band);
  /// Solves M X = B for the 3 columns of B in place. Allocates nothing after the first call.
  void SolveInPlace(Points* b);

 private:
  CholmodCommon common_;
  CholmodSolver solver_;
  CholmodSolveWorkspace work_;
  Eigen::Matrix<double, Eigen::Dynamic, 3> column_major_;  // CHOLMOD wants columns
};

}  // namespace viscera::mechanics
