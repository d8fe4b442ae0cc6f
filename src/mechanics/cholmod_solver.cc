#include "mechanics/cholmod_solver.h"

#include <algorithm>
#include <cstring>

#include "common/check.h"

namespace viscera::mechanics {

CholmodCommon::CholmodCommon() {
  cholmod_start(&common_);
  common_.print = 0;  // errors are reported through return values, not stderr
}

CholmodCommon::~CholmodCommon() { cholmod_finish(&common_); }

CholmodSolveWorkspace::~CholmodSolveWorkspace() {
  cholmod_free_dense(&x_, common_->get());
  cholmod_free_dense(&y_, common_->get());
  cholmod_free_dense(&e_, common_->get());
}

CholmodSolver::CholmodSolver(CholmodCommon* common, Kind kind) : common_(common), kind_(kind) {}

CholmodSolver::~CholmodSolver() {
  cholmod_free_factor(&factor_, common_->get());
  cholmod_free_sparse(&a_, common_->get());
}

void CholmodSolver::SetPattern(int n, const std::vector<int>& col_ptr,
                               const std::vector<int>& row_index) {
  VISCERA_DEMAND(static_cast<int>(col_ptr.size()) == n + 1);
  VISCERA_DEMAND(static_cast<int>(row_index.size()) == col_ptr[n]);
  cholmod_common* c = common_->get();
  cholmod_free_factor(&factor_, c);
  cholmod_free_sparse(&a_, c);
  n_ = n;
  a_ = cholmod_allocate_sparse(n, n, col_ptr[n], /*sorted=*/1, /*packed=*/1, /*stype=*/1,
                               CHOLMOD_REAL, c);
  VISCERA_DEMAND(a_ != nullptr);
  std::copy(col_ptr.begin(), col_ptr.end(), static_cast<int*>(a_->p));
  std::copy(row_index.begin(), row_index.end(), static_cast<int*>(a_->i));
  std::fill_n(static_cast<double*>(a_->x), col_ptr[n], 0.0);
  switch (kind_) {
    case Kind::kAuto: c->supernodal = CHOLMOD_AUTO; break;
    case Kind::kSimplicial: c->supernodal = CHOLMOD_SIMPLICIAL; break;
    case Kind::kSupernodal: c->supernodal = CHOLMOD_SUPERNODAL; break;
  }
  // LL' rather than LDL': the matrices here are positive definite, and an LL' simplicial
  // factor keeps its size on refactorization.
  c->final_ll = 1;
  // Natural ordering: a block-band matrix in its own order has no fill outside the band, and
  // a permuted factorization would transpose (allocate) on every refactorization.
  c->nmethods = 1;
  c->method[0].ordering = CHOLMOD_NATURAL;
  c->postorder = 0;
  factor_ = cholmod_analyze(a_, c);
  VISCERA_DEMAND(factor_ != nullptr);
}

double* CholmodSolver::values() { return static_cast<double*>(a_->x); }

bool CholmodSolver::Factorize() {
  cholmod_common* c = common_->get();
  const int ok = cholmod_factorize(a_, factor_, c);
  return ok && c->status == CHOLMOD_OK && factor_->minor == static_cast<size_t>(n_);
}

void CholmodSolver::SolveInPlace(double* b, int num_columns, CholmodSolveWorkspace* work) {
  cholmod_common* c = common_->get();
  // A dense header over the caller's memory: cholmod_solve2 only reads B.
  cholmod_dense rhs{};
  rhs.nrow = n_;
  rhs.ncol = num_columns;
  rhs.nzmax = static_cast<size_t>(n_) * num_columns;
  rhs.d = n_;
  rhs.x = b;
  rhs.xtype = CHOLMOD_REAL;
  rhs.dtype = CHOLMOD_DOUBLE;
  // A simplicial solve asks for Y of shape max(4, #rhs) x n but leaves it reshaped to its last
  // block of columns, so the next call would free and reallocate it: give it back the shape it
  // will ask for (its storage is large enough).
  if (!factor_->is_super && work->y_ != nullptr) {
    const size_t rows = std::max(4, num_columns);
    if (work->y_->nzmax >= rows * n_) {
      work->y_->nrow = rows;
      work->y_->ncol = n_;
      work->y_->d = rows;
    }
  }
  const int ok = cholmod_solve2(CHOLMOD_A, factor_, &rhs, nullptr, &work->x_, nullptr, &work->y_,
                                &work->e_, c);
  VISCERA_DEMAND(ok);
  std::memcpy(b, work->x_->x, sizeof(double) * rhs.nzmax);
}

CholmodBandSolver::CholmodBandSolver() : solver_(&common_), work_(&common_) {}

void CholmodBandSolver::Factor(
    const Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>& band) {
  const int n = static_cast<int>(band.rows());
  std::vector<int> col_ptr(n + 1, 0), row_index;
  std::vector<double> values;
  for (int j = 0; j < n; ++j) {
    for (int i = std::max(0, j - 3); i <= j; ++i) {
      row_index.push_back(i);
      values.push_back(band(i, j - i));
    }
    col_ptr[j + 1] = static_cast<int>(row_index.size());
  }
  solver_.SetPattern(n, col_ptr, row_index);
  std::copy(values.begin(), values.end(), solver_.values());
  ThrowUnless(solver_.Factorize(), "mass matrix is not positive definite");
  column_major_.resize(n, 3);
}

void CholmodBandSolver::SolveInPlace(Points* b) {
  column_major_ = *b;
  solver_.SolveInPlace(column_major_.data(), 3, &work_);
  *b = column_major_;
}

}  // namespace viscera::mechanics
