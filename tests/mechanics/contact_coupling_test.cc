// Self pairs in the implicit step: coupled exactly, a pile that moves as a block carries its
// true mass (no drag from its own contacts); the band-only coupling is the negative control.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "mechanics/implicit_euler.h"
#include "mechanics/mass_matrix.h"
#include "mechanics/step.h"
#include "scene/scene.h"

namespace viscera::mechanics {
namespace {

// The settled pile of scenes/fall.toml, as the start of a scene with no plane and no fluid drag.
ModelParams SettledPileWithoutSupport() {
  std::ifstream in(std::string(VISCERA_SOURCE_DIR) + "/scenes/fall.toml");
  std::stringstream text;
  text << in.rdbuf();
  ModelParams params = scene::ParseScene(text.str(), "fall.toml").model;
  Model model(params);
  State state = InitialState(model);
  Workspace workspace(model);
  for (int k = 0; k < 150; ++k) Step(model, {}, &state, &workspace);
  params.initial_q = state.q;
  params.obstacles.clear();
  params.damping = 0.0;
  return params;
}

// Mass-weighted mean velocity of the control points (m/s): the centre of mass's.
Vec3 CentreOfMassVelocity(const Model& model, const Points& qd) {
  const VecX w = MassRowSums(model.mass_band());
  return (w.transpose() * qd).transpose() / w.sum();
}

struct BlockPush {
  Vec3 velocity = Vec3::Zero();  // centre of mass after the push
  double mean_pairs = 0.0;       // self pairs in contact per step
};

// Every part of the pile pushed with the same acceleration g for 0.1 s: the contacts are
// internal forces, so the centre of mass must reach g * 0.1 s whatever they do.
BlockPush PushAsABlock(ModelParams params, double rate_hz, bool exact) {
  params.rate_hz = rate_hz;
  params.contacts.exact_pairs = exact;
  params.gravity = Vec3(3.0, 0.0, 0.0);
  Model model(params);
  State state = InitialState(model);
  Workspace workspace(model);
  BlockPush push;
  const int steps = static_cast<int>(std::lround(0.1 * rate_hz));
  for (int k = 0; k < steps; ++k) {
    Step(model, {}, &state, &workspace);
    push.mean_pairs += static_cast<double>(state.contacts.self) / steps;
  }
  push.velocity = CentreOfMassVelocity(model, state.qd);
  return push;
}

TEST(ContactCoupling, APileMovedAsABlockCarriesItsTrueMass) {
  const ModelParams pile = SettledPileWithoutSupport();
  const Vec3 expected(0.3, 0.0, 0.0);  // g t
  for (double rate : {100.0, 1000.0}) {
    const BlockPush exact = PushAsABlock(pile, rate, true);
    EXPECT_GT(exact.mean_pairs, 100.0)
        << rate << " Hz: the pile must stay packed for the test to mean anything";
    EXPECT_LT((exact.velocity - expected).norm(), 0.02 * expected.norm())
        << rate << " Hz: " << exact.velocity.transpose();
  }
  // Negative control: each side's own window only, 2 k n n^T: the contacts drag the block.
  const BlockPush band = PushAsABlock(pile, 100.0, false);
  EXPECT_LT(band.velocity.x(), 0.9 * expected.x()) << band.velocity.transpose();
}

TEST(ContactCoupling, ConjugateGradientsConvergeInAFewIterationsAtOneKilohertz) {
  ModelParams params = SettledPileWithoutSupport();
  params.rate_hz = 1000.0;
  Model model(params);
  State state = InitialState(model);
  Workspace workspace(model);
  auto* integrator = dynamic_cast<ImplicitEulerIntegrator*>(&workspace.integrator());
  ASSERT_NE(integrator, nullptr);
  for (int k = 0; k < 100; ++k) Step(model, {}, &state, &workspace);
  EXPECT_GT(integrator->cg_iterations(), 0);  // pairs were coupled
  EXPECT_EQ(integrator->cg_unconverged(), 0);
  EXPECT_LE(integrator->cg_iterations(), 100 * 10);  // warm starts: a few per step, not tens
}

// A settled pile (scenes/fall.toml after 2 s): its forces nearly cancel, so b is nearly 0 and a
// fraction of it is no scale for CG's stop; gravity's impulse over the sub-step is. With that
// floor the pile takes far fewer iterations and moves as with the strict stop: within
// micrometres over half a second, while its points still slide at up to ~1.5 cm/s. The pile
// slides under the law of the scene's settle (friction without a static phase): under Coulomb's
// law it rests, and a frozen pile would agree with any stop.
TEST(ContactCoupling, ASettledPileStopsAtGravitysScaleAndMovesAsWithTheStrictStop) {
  std::ifstream in(std::string(VISCERA_SOURCE_DIR) + "/scenes/fall.toml");
  std::stringstream text;
  text << in.rdbuf();
  ModelParams params = scene::ParseScene(text.str(), "fall.toml").model;
  params.contacts.friction_law = FrictionLaw::kRegularized;
  const Model model(params);
  State settled = InitialState(model);
  {
    Workspace workspace(model);
    for (int k = 0; k < 200; ++k) Step(model, {}, &settled, &workspace);
  }
  State floor_state = settled, strict_state = settled;
  Workspace floor_workspace(model), strict_workspace(model);
  auto* floor_cg = dynamic_cast<ImplicitEulerIntegrator*>(&floor_workspace.integrator());
  auto* strict_cg = dynamic_cast<ImplicitEulerIntegrator*>(&strict_workspace.integrator());
  ASSERT_TRUE(floor_cg != nullptr && strict_cg != nullptr);
  strict_cg->set_gravity_floor(0.0);
  double worst_distance = 0.0, fastest = 0.0;
  for (int k = 0; k < 50; ++k) {
    Step(model, {}, &floor_state, &floor_workspace);
    Step(model, {}, &strict_state, &strict_workspace);
    worst_distance =
        std::max(worst_distance, (floor_state.q - strict_state.q).rowwise().norm().maxCoeff());
    fastest = std::max(fastest, strict_state.qd.rowwise().norm().maxCoeff());
  }
  EXPECT_GT(settled.contacts.self, 100) << "the pile must be packed for the test to mean anything";
  EXPECT_GT(fastest, 5e-3) << "m/s: a frozen pile would agree with any stop";
  EXPECT_EQ(floor_cg->cg_unconverged(), 0);
  // Measured: 158 iterations against 622, 13 micrometres apart at most (1 % of R allowed).
  EXPECT_LT(floor_cg->cg_iterations(), strict_cg->cg_iterations() / 2);
  EXPECT_LT(worst_distance, 0.01 * params.radius) << worst_distance << " m";
}

}  // namespace
}  // namespace viscera::mechanics
