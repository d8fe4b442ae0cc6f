// Contacts on the shipped scenes: no sinking, containment, determinism, energy, detection.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "collision/spatial_grid.h"
#include "mechanics/step.h"
#include "scene/scene.h"

namespace viscera::mechanics {
namespace {

std::string SceneText(const char* name) {
  std::ifstream in(std::string(VISCERA_SOURCE_DIR) + "/scenes/" + name);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

struct Simulation {
  std::unique_ptr<Model> model;
  State state;
  std::unique_ptr<Workspace> workspace;
};

Simulation Start(const std::string& text) {
  Simulation r;
  r.model = std::make_unique<Model>(
      scene::ParseScene(text, std::string(VISCERA_SOURCE_DIR) + "/scenes/x.toml").model);
  r.state = InitialState(*r.model);
  r.workspace = std::make_unique<Workspace>(*r.model);
  return r;
}

void Advance(Simulation* r, double seconds) {
  const int steps = static_cast<int>(std::lround(seconds * r->model->params().rate_hz));
  for (int k = 0; k < steps; ++k) Step(*r->model, {}, &r->state, r->workspace.get());
}

TEST(Contacts, FallSettlesOnItsPlaneWithoutSinkingIntoItOrItself) {
  Simulation r = Start(SceneText("fall.toml"));
  Advance(&r, 4.0);
  const collision::SphereChain& chain = r.workspace->interactions()->chain();
  const double radius = chain.radius();
  const auto& spheres = chain.spheres();
  // Tolerance: no sphere sinks by more than 20 % of the radius.
  double lowest = 1.0, closest = 1.0;
  const int skip = static_cast<int>(std::floor(2.0 * radius / chain.spacing())) + 1;
  for (size_t a = 0; a < spheres.size(); ++a) {
    lowest = std::min(lowest, spheres[a].centre.z());
    for (size_t b = a + skip; b < spheres.size(); ++b)
      closest = std::min(closest, (spheres[a].centre - spheres[b].centre).norm());
  }
  EXPECT_GT(lowest, 0.8 * radius);
  EXPECT_GT(closest, 2.0 * radius - 0.2 * radius);
  EXPECT_LT(lowest, 1.2 * radius);  // it did land
  EXPECT_GT(r.state.contacts.self, 50);
  EXPECT_GT(r.state.contacts.environment, 50);
  EXPECT_LT(ComputeEnergies(*r.model, r.state.q, r.state.qd).kinetic, 1e-3);  // settled
}

TEST(Contacts, EnergyNeverGrowsWithoutInput) {
  Simulation r = Start(SceneText("fall.toml"));
  Interactions* in = r.workspace->interactions();
  double previous = ComputeEnergies(*r.model, r.state.q, r.state.qd, in).total();
  const double start = previous;
  for (int k = 0; k < 150; ++k) {  // the fall and its impact on the plane
    Step(*r.model, {}, &r.state, r.workspace.get());
    const double e = ComputeEnergies(*r.model, r.state.q, r.state.qd, in).total();
    ASSERT_LE(e, previous + 1e-6 * start) << "step " << k;
    previous = e;
  }
  EXPECT_LT(previous, 0.5 * start);  // the impact dissipated
}

TEST(Contacts, SameInputsGiveBitIdenticalStates) {
  Simulation a = Start(SceneText("fall.toml"));
  Simulation b = Start(SceneText("fall.toml"));
  Advance(&a, 0.6);
  Advance(&b, 0.6);
  ASSERT_EQ(a.state.q.size(), b.state.q.size());
  EXPECT_EQ(std::memcmp(a.state.q.data(), b.state.q.data(), sizeof(double) * a.state.q.size()), 0);
  EXPECT_EQ(std::memcmp(a.state.qd.data(), b.state.qd.data(), sizeof(double) * a.state.qd.size()),
            0);
}

// fall.toml with the impact limiter and the stiffening law alone: the impulses inside the implicit
// solve and the material spheres, on by default, switched off by its keys
// (docs/impacts.md). At μ 0.3: with the tissue card's 0.05 that path gains 0.5 mJ in one step
// of the impact (docs/impacts.md).
std::string LimiterOnlyFall() {
  std::string text = SceneText("fall.toml");
  const size_t table = text.find("[contacts]");
  EXPECT_NE(table, std::string::npos);
  text.insert(table + std::string("[contacts]").size(),
              "\nimpact_constraints = false\nspheres = \"arc_length\"\nself_friction = 0.3\n");
  const size_t friction = text.find("\nfriction = ");  // the line, replaced
  EXPECT_NE(friction, std::string::npos);
  text.replace(friction + 1, text.find('\n', friction + 1) - friction - 1, "friction = 0.3");
  return text;
}

TEST(Contacts, TheLimiterAloneNeverGainsEnergyOnTheShippedFallAndRerunsBitIdentically) {
  Simulation a = Start(LimiterOnlyFall());
  Simulation b = Start(LimiterOnlyFall());
  ASSERT_FALSE(a.model->params().contacts.impact_constraints);
  ASSERT_FALSE(a.model->params().contacts.spheres_follow_material);
  Interactions* in = a.workspace->interactions();
  double previous = ComputeEnergies(*a.model, a.state.q, a.state.qd, in).total();
  const double start = previous;
  for (int k = 0; k < 150; ++k) {  // the fall and its impact on the plane
    Step(*a.model, {}, &a.state, a.workspace.get());
    Step(*b.model, {}, &b.state, b.workspace.get());
    const double e = ComputeEnergies(*a.model, a.state.q, a.state.qd, in).total();
    ASSERT_LE(e, previous + 1e-6 * start) << "step " << k;
    previous = e;
  }
  EXPECT_LT(previous, 0.5 * start);  // the impact dissipated
  EXPECT_EQ(std::memcmp(a.state.q.data(), b.state.q.data(), sizeof(double) * a.state.q.size()), 0);
  EXPECT_EQ(std::memcmp(a.state.qd.data(), b.state.qd.data(), sizeof(double) * a.state.qd.size()),
            0);
}

// The goal: no pair deeper than a tenth of the radius at the end of any step, on every shipped
// scene with contacts, at its own rate and at 1 kHz, for 3 s from its start (the cavity from its
// settled pile; the fall through its landing). A scene that starts with its tube overlapping
// itself fails here: attached.toml's serpentine, with turns tighter than the tube (wavelength
// 10 cm), sank a pair 26 % of R deep in its first step until it was widened to 14 cm.
TEST(Contacts, NoShippedSceneSinksAPairDeeperThanATenthOfTheRadius) {
  int scenes = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(VISCERA_SOURCE_DIR) + "/scenes")) {
    if (entry.path().extension() != ".toml") continue;
    for (const double rate : {0.0, 1000.0}) {  // 0: the scene's own
      scene::Scene scene = scene::LoadSceneFile(entry.path().string());
      if (!scene.model.contacts.self && scene.model.obstacles.empty()) continue;
      if (rate > 0.0) scene::ChangeRate(&scene.model, rate);
      const Model model(scene.model);
      State state = InitialState(model);
      Workspace workspace(model);
      double deepest = 0.0, when = 0.0;
      const int steps = static_cast<int>(std::lround(3.0 * model.params().rate_hz));
      for (int k = 0; k < steps; ++k) {
        Step(model, {}, &state, &workspace);
        const double depth = -state.contacts.min_clearance / model.params().radius;
        if (!std::isnan(depth) && depth > deepest) deepest = depth, when = state.t;
      }
      EXPECT_LE(deepest, 0.10) << entry.path().filename() << " at " << model.params().rate_hz
                               << " Hz, t = " << when << " s";
      scenes += rate > 0.0 ? 1 : 0;
    }
  }
  EXPECT_GE(scenes, 5) << "the shipped scenes with contacts";
}

TEST(Contacts, NothingEverLeavesTheCavity) {
  // The cavity without its pre-settling: watch every step of the fall into the pile. (The
  // four-spring cavity: cavity.toml's mesentery starts 15 cm overstretched and needs its settling
  // to tighten gradually, docs/mechanics.md.)
  std::string text = SceneText("cavity_springs.toml");
  const size_t settle = text.find("\nsettle = ");
  ASSERT_NE(settle, std::string::npos);
  text.replace(settle + 1, text.find('\n', settle + 1) - settle - 1, "settle = 0.0");
  Simulation r = Start(text);
  const collision::Obstacle* cavity = nullptr;
  for (const collision::Obstacle& o : r.model->params().obstacles) {
    if (o.name == "cavity") cavity = &o;
  }
  ASSERT_NE(cavity, nullptr);
  const double radius = r.model->params().radius;
  double worst = 1.0;
  for (int k = 0; k < 300; ++k) {
    Step(*r.model, {}, &r.state, r.workspace.get());
    for (const collision::Sphere& s : r.workspace->interactions()->chain().spheres()) {
      Vec3 n;
      worst = std::min(worst, collision::SignedDistance(*cavity, s.centre, &n));
    }
  }
  // Every centre stays inside; the surface sinks into the wall by less than 20 % of the radius.
  EXPECT_GT(worst, 0.8 * radius);
}

TEST(Contacts, DetectorFindsExactlyTheBruteForcePairsOfAPile) {
  Simulation r = Start(SceneText("fall.toml"));
  Advance(&r, 1.5);
  const Interactions& in = *r.workspace->interactions();
  const auto& spheres = in.chain().spheres();
  const int skip =
      static_cast<int>(std::floor(2.0 * in.chain().radius() / in.chain().spacing())) + 1;
  collision::ContactDetector detector(in.chain().radius(), 0.003, true, skip);
  std::vector<collision::ContactCandidate> found;
  detector.Detect(spheres, {}, {}, &found);
  std::vector<std::pair<int, int>> grid;
  for (const auto& c : found) grid.emplace_back(c.a, c.b);
  std::sort(grid.begin(), grid.end());
  std::vector<Vec3> centres;
  for (const auto& s : spheres) centres.push_back(s.centre);
  std::vector<std::pair<int, int>> brute;
  for (const auto& p :
       collision::SpatialGrid::BruteForcePairs(centres, 2.0 * in.chain().radius() + 0.003)) {
    if (p.second - p.first >= skip) brute.push_back(p);
  }
  EXPECT_EQ(grid, brute);
  EXPECT_GT(brute.size(), 100u);
}

}  // namespace
}  // namespace viscera::mechanics
