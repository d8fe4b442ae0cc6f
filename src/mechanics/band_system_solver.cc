#include "mechanics/band_system_solver.h"

#include "mechanics/avx_clone.h"

#include <algorithm>
#include <array>

namespace viscera::mechanics {

BandSystemSolver::BandSystemSolver(int num_points, bool use_cholmod)
    : n_(num_points),
      use_cholmod_(use_cholmod),
      system_(num_points),
      solver_(&common_),
      solve_work_(&common_),
      solve_one_work_(&common_) {
  spare_.setZero(3 * n_);
  if (use_cholmod_) BuildPattern();
}

void BandSystemSolver::BuildPattern() {
  // Upper triangle of the 3N x 3N block band, column by column, rows sorted.
  const int dim = 3 * n_;
  std::vector<int> col_ptr(dim + 1, 0), row_index;
  slot_.assign(static_cast<size_t>(n_) * BlockBand::kWidth * 9, -1);
  for (int j = 0; j < n_; ++j) {
    for (int beta = 0; beta < 3; ++beta) {
      const int col = 3 * j + beta;
      for (int i = std::max(0, j - 3); i <= j; ++i) {
        for (int alpha = 0; alpha < 3; ++alpha) {
          const int row = 3 * i + alpha;
          if (row > col) continue;
          slot_[((static_cast<size_t>(i) * BlockBand::kWidth + (j - i)) * 3 + alpha) * 3 + beta] =
              static_cast<int>(row_index.size());
          row_index.push_back(row);
        }
      }
      col_ptr[col + 1] = static_cast<int>(row_index.size());
    }
  }
  solver_.SetPattern(dim, col_ptr, row_index);
}

VISCERA_AVX_CLONE void BandSystemSolver::Assemble(const Band& mass, const ForceJacobians& jacobians,
                                                  double damping_weight, double stiffness_weight) {
  for (int i = 0; i < n_; ++i) {
    for (int d = 0; d < BlockBand::kWidth && i + d < n_; ++d) {
      Mat3& block = system_.block(i, d);
      block = damping_weight * jacobians.damping.block(i, d) +
              stiffness_weight * jacobians.stiffness.block(i, d);
      block.diagonal().array() += mass(i, d);
    }
  }
}

bool BandSystemSolver::Factor() {
  if (!use_cholmod_) return band_factor_.Factor(system_);
  double* values = solver_.values();
  for (int i = 0; i < n_; ++i) {
    for (int d = 0; d < BlockBand::kWidth && i + d < n_; ++d) {
      const Mat3& block = system_.block(i, d);
      const int* s = &slot_[(static_cast<size_t>(i) * BlockBand::kWidth + d) * 9];
      for (int e = 0; e < 9; ++e) {
        if (s[e] >= 0) values[s[e]] = block(e / 3, e % 3);
      }
    }
  }
  return solver_.Factorize();
}

void BandSystemSolver::SolveInPlace(double* x, int first) {
  if (use_cholmod_) {
    solver_.SolveInPlace(x, 1, &solve_one_work_);
  } else {
    band_factor_.SolveInPlace(x, first);
  }
}

void BandSystemSolver::SolveTwoInPlace(double* a, double* b, int first) {
  if (use_cholmod_) {
    solver_.SolveInPlace(a, 1, &solve_one_work_);
    solver_.SolveInPlace(b, 1, &solve_one_work_);
  } else {
    band_factor_.SolveTwoInPlace(a, b, first);
  }
}

void BandSystemSolver::SolveColumns(MatX* rhs, Eigen::Index from, std::span<double* const> extra,
                                    std::span<const int> extra_first) {
  VISCERA_ASSERT(extra.size() == extra_first.size());
  if (use_cholmod_) {
    solver_.SolveInPlace(rhs->col(0).data(), 1, &solve_one_work_);
    const int cols = static_cast<int>(rhs->cols() - from);
    if (cols > 0) solver_.SolveInPlace(rhs->col(from).data(), cols, &solve_work_);
    for (double* x : extra) solver_.SolveInPlace(x, 1, &solve_one_work_);
    return;
  }
  // Four at a time: the solve's row-to-row chain, not its arithmetic, sets its time, and each
  // pass carries four columns in its lanes for about the time of one.
  std::array<double*, 4> pending{};
  int first = 0, count = 0;
  auto flush = [&] {
    switch (count) {
      case 1: band_factor_.SolveInPlace(pending[0], first); break;
      case 2: band_factor_.SolveTwoInPlace(pending[0], pending[1], first); break;
      case 3:
        band_factor_.SolveFourInPlace(pending[0], pending[1], pending[2], spare_.data(), first);
        break;
      case 4:
        band_factor_.SolveFourInPlace(pending[0], pending[1], pending[2], pending[3], first);
        break;
      default: break;
    }
    count = 0;
  };
  auto add = [&](double* x, int x_first) {
    first = count == 0 ? x_first : std::min(first, x_first);
    pending[count++] = x;
    if (count == 4) flush();
  };
  for (Eigen::Index k = 0; k < rhs->cols(); ++k) {
    if (k == 0 || k >= from) add(rhs->col(k).data(), 0);
  }
  for (size_t k = 0; k < extra.size(); ++k) add(extra[k], extra_first[k]);
  flush();
}

}  // namespace viscera::mechanics
