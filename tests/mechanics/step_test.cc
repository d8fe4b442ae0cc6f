#include "mechanics/step.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <new>
#include <vector>

#include "mechanics/implicit_euler.h"
#include "mechanics/stability.h"
#include "test_models.h"

// Counts heap allocations while `g_counting` is set, by interposing the C allocator itself:
// operator new (plain and aligned), Eigen's dynamic matrices (std::malloc / aligned_alloc),
// std containers and SuiteSparse (CHOLMOD) all end in one of these. Each forwards to glibc's
// own entry point, so nothing else changes. The canary tests below prove each path counts.
extern "C" {
void* __libc_malloc(size_t size);
void* __libc_calloc(size_t n, size_t size);
void* __libc_realloc(void* p, size_t size);
void* __libc_memalign(size_t alignment, size_t size);
void __libc_free(void* p);
}

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
volatile double g_sink = 0.0;  // keeps the canaries' allocations from being optimized out
void Count() {
  if (g_counting.load(std::memory_order_relaxed))
    g_allocations.fetch_add(1, std::memory_order_relaxed);
}

// Counts the allocations `body` makes.
template <typename Body>
long AllocationsIn(Body&& body) {
  g_allocations = 0;
  g_counting = true;
  body();
  g_counting = false;
  return g_allocations.load();
}
}  // namespace

extern "C" {
void* malloc(size_t size) {
  Count();
  return __libc_malloc(size);
}
void* calloc(size_t n, size_t size) {
  Count();
  return __libc_calloc(n, size);
}
void* realloc(void* p, size_t size) {
  Count();
  return __libc_realloc(p, size);
}
void free(void* p) { __libc_free(p); }
void* memalign(size_t alignment, size_t size) {
  Count();
  return __libc_memalign(alignment, size);
}
void* aligned_alloc(size_t alignment, size_t size) {
  Count();
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** out, size_t alignment, size_t size) {
  Count();
  if (alignment % sizeof(void*) != 0 || (alignment & (alignment - 1)) != 0) return EINVAL;
  *out = __libc_memalign(alignment, size);
  return *out == nullptr && size != 0 ? ENOMEM : 0;
}
}  // extern "C"

namespace viscera::mechanics {
namespace {

// The canary: each way a Step could allocate is seen by the counter. Without these, a
// counter that misses Eigen (as the first version of this test did) passes everything.
TEST(AllocationCounter, SeesEveryWayToAllocate) {
  EXPECT_EQ(AllocationsIn([] {}), 0);
  EXPECT_EQ(AllocationsIn([] {
              VecX tmp(10);  // the regression this test exists for: Eigen storage in Step
              tmp.setOnes();
              g_sink = tmp.sum();
            }),
            1);
  EXPECT_EQ(AllocationsIn([] {
              MatX m = MatX::Identity(1000, 1000);
              g_sink = m.trace();
            }),
            1);
  EXPECT_EQ(AllocationsIn([] {
              std::vector<int> v(10, 1);
              g_sink = v[3];
            }),
            1);
  struct alignas(64) Wide {
    double x[8];
  };
  EXPECT_EQ(AllocationsIn([] {
              Wide* volatile w = new Wide();  // aligned operator new (volatile: not elided)
              g_sink = w->x[0];
              delete w;
            }),
            1);
  EXPECT_EQ(AllocationsIn([] {
              void* p = nullptr;
              ASSERT_EQ(posix_memalign(&p, 64, 100), 0);
              std::free(p);
              std::free(std::calloc(4, 8));
              std::free(std::realloc(nullptr, 8));
              std::free(aligned_alloc(64, 128));
            }),
            4);
}

class StepAllocation : public ::testing::TestWithParam<std::tuple<IntegratorKind, MassSolverKind>> {
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
  p.linear_solver = p.mass_solver == MassSolverKind::kCholmod ? LinearSolverKind::kCholmod
                                                              : LinearSolverKind::kBlockBand;
  p.substeps = EstimateStability(Model(p), InitialState(Model(p))).stable_substeps;
  const Model model(p);
  State state = InitialState(model);
  Workspace ws(model);
  const PointLoad load{0.3, Vec3(0.0, 0.1, 0.0)};
  const StepInputs inputs{std::span<const PointLoad>(&load, 1), {}};
  for (int k = 0; k < 3; ++k) Step(model, inputs, &state, &ws);  // warm-up sizes the buffers

  EXPECT_EQ(AllocationsIn([&] {
              for (int k = 0; k < 50; ++k) Step(model, inputs, &state, &ws);
            }),
            0);
  EXPECT_EQ(state.nonfinite_resets, 0);
  EXPECT_GT((state.q - p.initial_q).norm(), 1e-3);  // the steps did something
}

INSTANTIATE_TEST_SUITE_P(
    AllIntegrators, StepAllocation,
    ::testing::Combine(::testing::Values(IntegratorKind::kRk4, IntegratorKind::kImplicitEuler),
                       ::testing::Values(MassSolverKind::kBanded, MassSolverKind::kCholmod)));

// Param: impacts held inside the implicit solve ([contacts] impact_constraints, spheres =
// "material").
class StepAllocationWithContacts : public ::testing::TestWithParam<bool> {};

TEST_P(StepAllocationWithContacts, ContactsAndToolsAllocateNothingInSteadyState) {
  ModelParams p = testing::StraightChain(60, 1.0);
  p.contacts.impact_constraints = GetParam();
  p.contacts.spheres_follow_material = GetParam();
  for (int i = 0; i < 60; ++i)
    p.initial_q.row(i) << 0.2 * std::cos(0.1 * i), 0.2 * std::sin(0.1 * i), 0.05 + 0.0005 * i;
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
  for (int k = 0; k < 100; ++k)
    Step(model, inputs, &state, &ws);  // fall, land, grasp: sizes settle

  EXPECT_EQ(AllocationsIn([&] {
              for (int k = 0; k < 50; ++k) Step(model, inputs, &state, &ws);
            }),
            0);
  EXPECT_GT(state.contacts.environment, 0);
}

INSTANTIATE_TEST_SUITE_P(ImpactsHeld, StepAllocationWithContacts, ::testing::Bool());

// A sub-step done again as halves (ImplicitEulerIntegrator's linearization guard) reuses the
// integrator's buffers: a slack chain pulled sideways by a spring stretched 15 cm past its rest.
TEST(StepAllocation, HalvedSubstepsAllocateNothing) {
  ModelParams p = testing::StraightChain(40, 1.0);
  p.stretch_stiffness = 100.0;
  p.integrator = IntegratorKind::kImplicitEuler;
  p.attachments.push_back(
      {.s = 0.5, .point = Vec3(0.5, 0.3, 0.0), .stiffness = 20.0, .rest_length = 0.15});
  const Model model(p);
  const State start = InitialState(model);
  State state = start;
  Workspace ws(model);
  for (int k = 0; k < 20; ++k) Step(model, {}, &state, &ws);  // sizes settle
  auto& integrator = dynamic_cast<ImplicitEulerIntegrator&>(ws.integrator());
  const int64_t halved = integrator.halved_substeps();
  ASSERT_GT(halved, 0);
  state = start;  // same sizes: the copy reuses storage
  EXPECT_EQ(AllocationsIn([&] { Step(model, {}, &state, &ws); }), 0);
  EXPECT_GT(integrator.halved_substeps(), halved);  // the counted step was halved
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
