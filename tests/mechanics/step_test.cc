#include "mechanics/step.h"

#include <SuiteSparse_config.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include "mechanics/stability.h"
#include "test_models.h"

// Counts heap allocations while `g_counting` is set: C++ operator new, and SuiteSparse's
// allocator hooks (CHOLMOD allocates through them, not through new).
namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};

void* CountedMalloc(size_t size) {
  if (g_counting) ++g_allocations;
  return std::malloc(size);
}
void* CountedCalloc(size_t n, size_t size) {
  if (g_counting) ++g_allocations;
  return std::calloc(n, size);
}
void* CountedRealloc(void* p, size_t size) {
  if (g_counting) ++g_allocations;
  return std::realloc(p, size);
}
}  // namespace

// GCC cannot see that these two replace each other's allocator.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(size_t size) {
  if (g_counting) ++g_allocations;
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, size_t) noexcept { std::free(p); }

namespace viscera::mechanics {
namespace {

class StepAllocation : public ::testing::TestWithParam<std::tuple<IntegratorKind, MassSolverKind>> {
 protected:
  void SetUp() override {
    SuiteSparse_config.malloc_func = CountedMalloc;
    SuiteSparse_config.calloc_func = CountedCalloc;
    SuiteSparse_config.realloc_func = CountedRealloc;
  }
};

TEST_P(StepAllocation, StepAllocatesNothingInSteadyState) {
  ModelParams p = testing::StraightChain(50, 1.0, 1.05);
  p.initial_q = testing::Perturbed(p.initial_q, 0.01, 3);
  p.gravity = Vec3(0.0, 0.0, -9.81);
  p.stretch_stiffness = 50.0;
  p.bend_stiffness = 1e-4;
  p.continuous_stretch = 0.5;
  p.damping = 0.5;
  p.spring_damping = 1.0;
  p.pinned = {0.0, 0.6};
  p.attachments.push_back({1.0, std::nullopt, 10.0, 0.1, 0.0});
  p.integrator = std::get<0>(GetParam());
  p.mass_solver = std::get<1>(GetParam());
  // The CHOLMOD variant also solves the implicit system with CHOLMOD.
  p.linear_solver = p.mass_solver == MassSolverKind::kCholmod ? LinearSolverKind::kCholmod : LinearSolverKind::kBlockBand;
  p.substeps = EstimateStability(Model(p), InitialState(Model(p))).stable_substeps;
  const Model model(p);
  State state = InitialState(model);
  Workspace ws(model);
  const PointLoad load{0.3, Vec3(0.0, 0.1, 0.0)};
  const StepInputs inputs{std::span<const PointLoad>(&load, 1), {}};
  for (int k = 0; k < 3; ++k) Step(model, inputs, &state, &ws);  // warm-up sizes the buffers

  g_allocations = 0;
  g_counting = true;
  for (int k = 0; k < 50; ++k) Step(model, inputs, &state, &ws);
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_EQ(state.nonfinite_resets, 0);
  EXPECT_GT((state.q - p.initial_q).norm(), 1e-3);  // the steps did something
}

INSTANTIATE_TEST_SUITE_P(
    AllIntegrators, StepAllocation,
    ::testing::Combine(::testing::Values(IntegratorKind::kRk4, IntegratorKind::kImplicitEuler),
                       ::testing::Values(MassSolverKind::kBanded, MassSolverKind::kCholmod)));

TEST(StepAllocationWithContacts, ContactsAndToolsAllocateNothingInSteadyState) {
  SuiteSparse_config.malloc_func = CountedMalloc;
  ModelParams p = testing::StraightChain(60, 1.0);
  for (int i = 0; i < 60; ++i) p.initial_q.row(i) << 0.2 * std::cos(0.1 * i), 0.2 * std::sin(0.1 * i), 0.05 + 0.0005 * i;
  p.gravity = Vec3(0.0, 0.0, -9.81);
  p.stretch_stiffness = 50.0;
  p.damping = 1.0;
  p.integrator = IntegratorKind::kImplicitEuler;
  p.contacts.self = true;
  collision::Obstacle plane;
  p.obstacles.push_back(plane);
  ToolParams tool;
  tool.name = "t";
  tool.port = Vec3(0.0, 0.0, 0.4);
  p.tools.push_back(tool);
  const Model model(p);
  State state = InitialState(model);
  Workspace ws(model);
  ToolTarget target;
  target.tip = Vec3(0.2, 0.0, 0.03);
  target.jaw = 0.0;  // grasp on the way down
  const StepInputs inputs{{}, std::span<const ToolTarget>(&target, 1)};
  for (int k = 0; k < 100; ++k) Step(model, inputs, &state, &ws);  // fall, land, grasp: sizes settle

  g_allocations = 0;
  g_counting = true;
  for (int k = 0; k < 50; ++k) Step(model, inputs, &state, &ws);
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_GT(state.contacts.environment, 0);
}

TEST(Step, NonFiniteStateResetsToStartAndIsCounted) {
  ModelParams p = testing::StraightChain(10);
  const Model model(p);
  State state = InitialState(model);
  Workspace ws(model);
  state.qd(3, 1) = std::numeric_limits<double>::quiet_NaN();
  Step(model, {}, &state, &ws);
  EXPECT_EQ(state.nonfinite_resets, 1);
  EXPECT_TRUE(state.q.allFinite());
  EXPECT_TRUE(state.qd.isZero());
  EXPECT_EQ(state.steps, 1);
}

}  // namespace
}  // namespace viscera::mechanics
