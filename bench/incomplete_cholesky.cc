#include "incomplete_cholesky.h"

#include <Eigen/OrderingMethods>

#include <string>
#include <vector>

namespace viscera::bench {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

// `lower` with `fill` explicit zeros added to each column, at the nearest rows below the
// diagonal it does not hold (the diagonal stays first, as Eigen's ICT requires).
SparseMatrix Padded(const SparseMatrix& lower, int fill) {
  const int n = static_cast<int>(lower.cols());
  std::vector<Eigen::Triplet<double, int>> entries;
  entries.reserve(lower.nonZeros() + static_cast<size_t>(fill) * n);
  std::vector<char> held(n, 0);
  for (int col = 0; col < n; ++col) {
    for (SparseMatrix::InnerIterator it(lower, col); it; ++it) {
      entries.emplace_back(it.row(), col, it.value());
      held[it.row()] = 1;
    }
    int added = 0;
    for (int row = col + 1; row < n && added < fill; ++row) {
      if (held[row]) continue;
      entries.emplace_back(row, col, 0.0);
      ++added;
    }
    for (SparseMatrix::InnerIterator it(lower, col); it; ++it) held[it.row()] = 0;
  }
  SparseMatrix padded(n, n);
  padded.setFromTriplets(entries.begin(), entries.end());  // sorted rows: the diagonal first
  return padded;
}

}  // namespace

IncompleteCholeskyPreconditioner::IncompleteCholeskyPreconditioner(IcOrdering ordering, int fill)
    : ordering_(ordering), fill_(fill) {}

std::string IncompleteCholeskyPreconditioner::name() const {
  return std::string("IC ") + (ordering_ == IcOrdering::kAmd ? "AMD" : "natural") + " +" +
         std::to_string(fill_);
}

bool IncompleteCholeskyPreconditioner::Factor(const SparseUpper& a, double w, const VecX& u) {
  const Eigen::Map<const SparseMatrix> upper(a.n, a.n, a.nonzeros(), a.col_ptr.data(), a.row.data(),
                                             a.value.data());
  // The ordering, then P A_s P^T's lower triangle, padded for the fill.
  if (ordering_ == IcOrdering::kAmd) {
    Eigen::AMDOrdering<int>()(upper.selfadjointView<Eigen::Upper>(), permutation_);
    permuted_.resize(a.n, a.n);
    permuted_.selfadjointView<Eigen::Lower>() =
        upper.selfadjointView<Eigen::Upper>().twistedBy(permutation_);
  } else {
    permutation_.resize(0);
    permuted_ = SparseMatrix(upper.transpose());
  }
  if (fill_ > 0) permuted_ = Padded(permuted_, fill_);
  ict_.compute(permuted_);
  if (ict_.info() != Eigen::Success) return false;
  l_ = ict_.matrixL();
  l_.prune([](int, int, double value) { return value != 0.0; });
  scale_ = ict_.scalingS();
  // The rank-one term: z = (L L^T)^-1 u for Sherman-Morrison.
  w_ = w;
  u_ = u;
  z_ = u;
  SolveFactor(&z_);
  denominator_ = 1.0 + w_ * u_.dot(z_);
  return true;
}

double IncompleteCholeskyPreconditioner::factor_flops() const {
  double flops = 0.0;
  for (int col = 0; col < l_.cols(); ++col) {
    const double below =
        static_cast<double>(l_.outerIndexPtr()[col + 1] - l_.outerIndexPtr()[col] - 1);
    flops += below * (below + 1.0);
  }
  return flops;
}

void IncompleteCholeskyPreconditioner::SolveFactor(VecX* x) const {
  // Eigen's ICT factors S P A P^T S = L L^T (S its scaling).
  if (permutation_.size() > 0) {
    scratch_.noalias() = permutation_ * *x;
  } else {
    scratch_ = *x;
  }
  scratch_.array() *= scale_.array();
  l_.triangularView<Eigen::Lower>().solveInPlace(scratch_);
  l_.transpose().triangularView<Eigen::Upper>().solveInPlace(scratch_);
  scratch_.array() *= scale_.array();
  if (permutation_.size() > 0) {
    x->noalias() = permutation_.inverse() * scratch_;
  } else {
    *x = scratch_;
  }
}

void IncompleteCholeskyPreconditioner::Apply(VecX* x) const {
  SolveFactor(x);
  if (w_ > 0.0) *x -= (w_ * u_.dot(*x) / denominator_) * z_;
}

double LevelZeroMultiplyAdds(const SparseUpper& a, bool band_only) {
  auto kept = [&](int row, int col) {
    return !band_only || col / 3 - row / 3 < mechanics::BlockBand::kWidth;
  };
  // below[k]: the rows under the diagonal of L's column k (A_s's upper triangle by rows).
  std::vector<std::vector<int>> below(a.n);
  for (int col = 0; col < a.n; ++col) {
    for (int e = a.col_ptr[col]; e < a.col_ptr[col + 1]; ++e) {
      if (a.row[e] < col && kept(a.row[e], col)) below[a.row[e]].push_back(col);
    }
  }
  // Left-looking: column j takes L(i, k) L(j, k) from each column k < j with L(j, k), for the
  // rows i >= j that column j holds.
  std::vector<char> held(a.n, 0);
  double updates = 0.0;
  for (int j = 0; j < a.n; ++j) {
    held[j] = 1;
    for (const int i : below[j]) held[i] = 1;
    for (int e = a.col_ptr[j]; e < a.col_ptr[j + 1]; ++e) {
      const int k = a.row[e];
      if (k >= j || !kept(k, j)) continue;
      for (const int i : below[k]) updates += i >= j && held[i];
    }
    held[j] = 0;
    for (const int i : below[j]) held[i] = 0;
  }
  return updates;
}

}  // namespace viscera::bench
