// The exact implicit matrix assembled for a direct solver (bench/exact_system.h, measured by
// bench_direct_coupling against the step's CG) is the step's own: on a real sub-step of the
// fall's landing, CHOLMOD's solve of A x = b is CG's converged answer on the step's product.
#include <gtest/gtest.h>

#include "exact_system.h"
#include "fall_scene.h"
#include "mechanics/step.h"

namespace viscera::bench {
namespace {

using mechanics::ImplicitEulerIntegrator;

TEST(DirectCoupling, CholmodOnTheAssembledMatrixIsCgsConvergedAnswer) {
  const mechanics::Model model(FallParams(250));
  ASSERT_TRUE(model.pins().empty());
  mechanics::Workspace workspace(model);
  mechanics::State state = mechanics::InitialState(model);
  for (int k = 0; k < 50; ++k) mechanics::Step(model, {}, &state, &workspace);  // 0.5 s: landing
  const auto& integrator = dynamic_cast<const ImplicitEulerIntegrator&>(workspace.integrator());
  const mechanics::Interactions& interactions = *workspace.interactions();
  ASSERT_GT(interactions.coupled_pairs(), 20);  // the last sub-step's pairs, still weighed for A

  const SparseUpper a = AssembleExact(integrator, interactions);
  EXPECT_EQ(a.n, 3 * model.num_points());
  EXPECT_FALSE(CoupledBlocks(a).empty());
  const double w = integrator.rank_one_weight();
  const VecX u = Eigen::Map<const VecX>(integrator.rank_one_u().data(), a.n);
  const VecX& b = integrator.last_rhs();
  ASSERT_GT(b.norm(), 0.0);

  // The same product as the step's, on any vector.
  const VecX probe = VecX::Random(a.n);
  VecX assembled, step;
  MultiplySymmetric(a, w, u, probe, &assembled);
  integrator.MultiplyExact(probe, &step);
  EXPECT_LT((assembled - step).norm(), 1e-12 * step.norm());

  mechanics::CholmodCommon common;
  DirectSolver direct(&common, Ordering::kAmd, /*supernodal=*/false);
  direct.Analyze(a);
  ASSERT_TRUE(direct.Factorize(a));
  EXPECT_GT(direct.factor_nonzeros(), a.nonzeros());  // the pairs fill in
  VecX x = b, z;
  direct.SolveWithRankOne(w, u, &x, &z);

  const BandPreconditioner band(integrator);
  VecX converged;
  const int iterations = SolveByCg(integrator, band, b, 1e-12, 500, &converged);
  EXPECT_LT(iterations, 500);
  EXPECT_LT((x - converged).norm(), 1e-8 * converged.norm()) << iterations << " CG iterations";

  // The pairs' common modes matter here: the band system's answer is far from it.
  VecX banded = b;
  band.Apply(&banded);
  EXPECT_GT((banded - converged).norm(), 1e-3 * converged.norm());
}

}  // namespace
}  // namespace viscera::bench
