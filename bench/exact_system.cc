#include "exact_system.h"

#include <algorithm>
#include <cstring>

#include "common/check.h"
#include "mechanics/conjugate_gradient.h"

namespace viscera::bench {

SparseUpper AssembleExact(const mechanics::ImplicitSystemView& system,
                          const mechanics::Interactions& interactions) {
  const mechanics::BlockBand& band = system.band_system();
  const int points = band.n();
  SparseUpper a;
  a.n = 3 * points;
  a.col_ptr.assign(a.n + 1, 0);
  std::vector<double> unit(a.n, 0.0), common(a.n, 0.0);
  for (int col = 0; col < a.n; ++col) {
    const int point = col / 3, beta = col % 3;
    unit[col] = 1.0;
    std::fill(common.begin(), common.end(), 0.0);
    interactions.AddCommonModeTerms(unit.data(), common.data());
    unit[col] = 0.0;
    const int band_first = 3 * std::max(0, point - (mechanics::BlockBand::kWidth - 1));
    for (int row = 0; row < band_first; ++row) {
      if (common[row] == 0.0) continue;
      a.row.push_back(row);
      a.value.push_back(common[row]);
    }
    for (int row = band_first; row <= col; ++row) {
      const int i = row / 3;
      a.row.push_back(row);
      a.value.push_back(band.block(i, point - i)(row % 3, beta) + common[row]);
    }
    a.col_ptr[col + 1] = static_cast<int>(a.row.size());
  }
  return a;
}

std::vector<std::pair<int, int>> CoupledBlocks(const SparseUpper& a) {
  std::vector<std::pair<int, int>> blocks;
  for (int col = 0; col < a.n; ++col) {
    for (int k = a.col_ptr[col]; k < a.col_ptr[col + 1]; ++k) {
      const int i = a.row[k] / 3, j = col / 3;
      if (j - i >= mechanics::BlockBand::kWidth) blocks.emplace_back(i, j);
    }
  }
  std::sort(blocks.begin(), blocks.end());
  blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());
  return blocks;
}

void MultiplySymmetric(const SparseUpper& a, double w, const VecX& u, const VecX& x, VecX* y) {
  y->setZero(a.n);
  for (int col = 0; col < a.n; ++col) {
    for (int k = a.col_ptr[col]; k < a.col_ptr[col + 1]; ++k) {
      const int row = a.row[k];
      (*y)(row) += a.value[k] * x(col);
      if (row != col) (*y)(col) += a.value[k] * x(row);
    }
  }
  if (w > 0.0) *y += (w * u.dot(x)) * u;
}

const char* OrderingName(Ordering ordering) {
  switch (ordering) {
    case Ordering::kNatural: return "natural";
    case Ordering::kAmd: return "AMD";
    case Ordering::kMetis: return "METIS";
    case Ordering::kNesdis: return "NESDIS";
  }
  return "?";
}

DirectSolver::DirectSolver(mechanics::CholmodCommon* common, Ordering ordering, bool supernodal)
    : common_(common->get()), ordering_(ordering), supernodal_(supernodal) {}

DirectSolver::~DirectSolver() {
  cholmod_free_dense(&x_, common_);
  cholmod_free_dense(&y_, common_);
  cholmod_free_dense(&e_, common_);
  cholmod_free_factor(&factor_, common_);
  cholmod_free_sparse(&a_, common_);
}

void DirectSolver::Analyze(const SparseUpper& a) {
  cholmod_free_factor(&factor_, common_);
  cholmod_free_sparse(&a_, common_);
  a_ = cholmod_allocate_sparse(a.n, a.n, a.row.size(), /*sorted=*/1, /*packed=*/1, /*stype=*/1,
                               CHOLMOD_REAL, common_);
  VISCERA_DEMAND(a_ != nullptr);
  std::copy(a.col_ptr.begin(), a.col_ptr.end(), static_cast<int*>(a_->p));
  std::copy(a.row.begin(), a.row.end(), static_cast<int*>(a_->i));
  std::copy(a.value.begin(), a.value.end(), static_cast<double*>(a_->x));
  common_->supernodal = supernodal_ ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
  common_->final_ll = 1;
  common_->nmethods = 1;
  common_->postorder = 1;
  switch (ordering_) {
    case Ordering::kNatural:
      common_->method[0].ordering = CHOLMOD_NATURAL;
      common_->postorder = 0;
      break;
    case Ordering::kAmd: common_->method[0].ordering = CHOLMOD_AMD; break;
    case Ordering::kMetis: common_->method[0].ordering = CHOLMOD_METIS; break;
    case Ordering::kNesdis: common_->method[0].ordering = CHOLMOD_NESDIS; break;
  }
  factor_ = cholmod_analyze(a_, common_);
  VISCERA_DEMAND(factor_ != nullptr && common_->status == CHOLMOD_OK);
  lnz_ = common_->lnz;
  flops_ = common_->fl;
}

bool DirectSolver::Factorize(const SparseUpper& a) {
  VISCERA_DEMAND(a_ != nullptr && a.row.size() == a_->nzmax);
  std::copy(a.value.begin(), a.value.end(), static_cast<double*>(a_->x));
  const int ok = cholmod_factorize(a_, factor_, common_);
  return ok && common_->status == CHOLMOD_OK && factor_->minor == a_->nrow;
}

void DirectSolver::Solve(VecX* x) {
  cholmod_dense rhs{};
  rhs.nrow = rhs.nzmax = rhs.d = x->size();
  rhs.ncol = 1;
  rhs.x = x->data();
  rhs.xtype = CHOLMOD_REAL;
  rhs.dtype = CHOLMOD_DOUBLE;
  VISCERA_DEMAND(
      cholmod_solve2(CHOLMOD_A, factor_, &rhs, nullptr, &x_, nullptr, &y_, &e_, common_));
  std::memcpy(x->data(), x_->x, sizeof(double) * x->size());
}

void DirectSolver::SolveWithRankOne(double w, const VecX& u, VecX* x, VecX* z) {
  Solve(x);
  if (w == 0.0) return;
  *z = u;
  Solve(z);
  *x -= (w * u.dot(*x) / (1.0 + w * u.dot(*z))) * *z;
}

BandPreconditioner::BandPreconditioner(const mechanics::ImplicitSystemView& system)
    : w_(system.rank_one_weight()),
      u_(Eigen::Map<const VecX>(system.rank_one_u().data(), system.rank_one_u().size())) {
  VISCERA_DEMAND(factor_.Factor(system.band_system()));
  z_ = u_;
  factor_.SolveInPlace(z_.data());
  denominator_ = 1.0 + w_ * u_.dot(z_);
}

void BandPreconditioner::Apply(VecX* x) const {
  factor_.SolveInPlace(x->data());
  if (w_ > 0.0) *x -= (w_ * u_.dot(*x) / denominator_) * z_;
}

int ContinueCg(const mechanics::ImplicitSystemView& system, const Preconditioner& preconditioner,
               double stop, double relative, int max_iterations, VecX* x, VecX* r) {
  mechanics::PreconditionedCg cg;
  cg.Resize(r->size());
  cg.residual() = *r;
  const int it =
      cg.Continue([&](const Eigen::Ref<const VecX>& v, VecX* y) { system.MultiplyExact(v, y); },
                  [&](VecX* v) { preconditioner.Apply(v); }, stop, relative, max_iterations, *x,
                  nullptr)
          .iterations;
  *r = cg.residual();
  return it;
}

int SolveByCg(const mechanics::ImplicitSystemView& system, const Preconditioner& preconditioner,
              const VecX& b, double tolerance, int max_iterations, VecX* x) {
  x->setZero(b.size());
  VecX r = b;
  return ContinueCg(system, preconditioner, 0.0, tolerance, max_iterations, x, &r);
}

VecX CgWarmStart(const BandPreconditioner& band, const VecX& b, const VecX& extrapolated) {
  VecX x = b;
  band.Apply(&x);
  return x + extrapolated;
}

}  // namespace viscera::bench
