#include "collision/verlet_list.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <tuple>

namespace viscera::collision {
namespace {

using Key = std::tuple<int, int, int>;

Key KeyOf(const ContactCandidate& c) { return {static_cast<int>(c.kind), c.a, c.b}; }

// A dense pile of spheres that mostly jitters, a group that moves together (a grasped loop),
// a tool that sweeps through, and now and then everything moving at once (a fall); the asked
// margin changes with the speed, as Interactions asks it.
struct Scene {
  static constexpr double kRadius = 0.01;
  std::mt19937 rng{7};
  std::vector<Sphere> spheres;
  std::vector<Obstacle> obstacles;
  std::vector<ToolCapsule> tools;

  Scene() {
    std::uniform_real_distribution<double> box(-0.06, 0.06);
    spheres.resize(200);
    for (Sphere& s : spheres) s.centre = Vec3(box(rng), box(rng), box(rng));
    Obstacle ball;
    ball.kind = ObstacleKind::kSphere;
    ball.centre = Vec3(0.0, 0.0, -0.09);
    ball.radius = 0.05;
    obstacles.push_back(ball);
    ToolCapsule tool;
    tool.present = true;
    tool.port = Vec3(0.0, 0.0, 0.2);
    tool.tip = Vec3(-0.05, 0.0, 0.0);
    tool.radius = 0.005;
    tools.push_back(tool);
  }

  void Move(int k) {
    std::uniform_real_distribution<double> jitter(-5e-5, 5e-5);
    const double angle = 0.01 * k;
    const Vec3 carry = 8e-4 * Vec3(std::cos(angle), std::sin(angle), 0.3 * std::sin(3.0 * angle));
    const bool fall = k % 700 > 650;
    for (size_t i = 0; i < spheres.size(); ++i) {
      Vec3& c = spheres[i].centre;
      if (fall) {
        c.z() -= 3e-3;
      } else if (i >= 40 && i < 60) {
        c += carry;  // a carried loop ...
      } else if (i >= 60 && i < 80) {
        c -= carry;  // ... and one carried the other way: pairs that close in head-on
      } else if (i >= 80 && i < 100) {
        // a group that swings back and forth by about the list's skin (a beating organ)
        c.x() += 2.5e-3 * (std::sin(0.15 * (k + 1)) - std::sin(0.15 * k));
      } else {
        // the rest shears slowly (x velocity growing with y), so gaps keep closing
        c += Vec3(2e-4 * c.y() / 0.06 + jitter(rng), jitter(rng), jitter(rng));
      }
      for (int a = 0; a < 3; ++a) {
        if (c(a) < -0.1) c(a) += 0.2;  // wraps: a teleport that only a search can follow
        if (c(a) > 0.1) c(a) -= 0.2;
      }
    }
    tools[0].tip += 1.2 * carry;
  }
};

TEST(VerletList, KeepsEveryPairWithinTheMarginThroughPartialAndWholeSearches) {
  Scene scene;
  const double margin0 = 0.25 * Scene::kRadius;
  VerletList list(ContactDetector(Scene::kRadius, margin0, true, 1), 0.5 * Scene::kRadius);
  ContactDetector reference(Scene::kRadius, margin0, true, 1);
  std::vector<ContactCandidate> expected;
  int64_t checked = 0;
  for (int k = 0; k < 3000; ++k) {
    scene.Move(k);
    const double margin = margin0 * (1.0 + 0.8 * std::abs(std::sin(0.02 * k)));
    list.Update(scene.spheres, scene.obstacles, scene.tools, margin);
    reference.Detect(scene.spheres, scene.obstacles, scene.tools, &expected, margin);
    std::set<Key> kept;
    for (const ContactCandidate& c : list.candidates()) {
      ASSERT_TRUE(kept.insert(KeyOf(c)).second) << "duplicate candidate at step " << k;
    }
    for (const ContactCandidate& c : expected) {
      ASSERT_TRUE(kept.count(KeyOf(c)))
          << "step " << k << ": pair (" << static_cast<int>(c.kind) << ", " << c.a << ", " << c.b
          << ") within the margin is missing";
    }
    checked += static_cast<int64_t>(expected.size());
  }
  // Every path was taken: partial searches (the carried group, the tool), whole ones (falls).
  EXPECT_GT(list.partial_searches(), 30);
  EXPECT_GT(list.searches(), 4);
  EXPECT_GT(checked, 100000);
}

// The case a partial search must remember (drift_): B moved a little before C was searched
// again next to it, then B turns round and both close in. The pair's last look was at C's
// search, when B was already off its own reference; B's travel since that reference
// understates how far it moved since the look.
TEST(VerletList, APairLookedAtInAPartialSearchIsFoundWhenTheBodyLeftAloneTurnsRound) {
  constexpr double kRadius = 0.01, kMargin = 0.0025, kSkin = 0.005;
  std::vector<Sphere> spheres(21);
  for (int i = 0; i < 19; ++i) spheres[i].centre = Vec3(0.0, 1.0 + 0.1 * i, 0.0);  // far away
  Sphere& b = spheres[19];
  Sphere& c = spheres[20];
  b.centre = Vec3::Zero();
  c.centre = Vec3(1.0, 0.0, 0.0);
  const std::vector<Obstacle> none;
  const std::vector<ToolCapsule> no_tools;
  VerletList list(ContactDetector(kRadius, kMargin, true, 1), kSkin);
  list.Update(spheres, none, no_tools, kMargin);
  ASSERT_EQ(list.searches(), 1);

  b.centre.x() += 0.0016;  // under a third of the spare margin: B is left alone below
  list.Update(spheres, none, no_tools, kMargin);
  // C lands just outside the searched margin from B, on B's other side: a partial search.
  const double searched = kMargin + kSkin;
  c.centre = Vec3(b.centre.x() - (2.0 * kRadius + searched + 1e-4), 0.0, 0.0);
  list.Update(spheres, none, no_tools, kMargin);
  ASSERT_EQ(list.partial_searches(), 1);
  ASSERT_EQ(list.searches(), 1);

  ContactDetector reference(kRadius, kMargin, true, 1);
  std::vector<ContactCandidate> expected;
  for (int k = 0; k < 12; ++k) {
    // B back past its reference toward C, and C toward B: each travels less than half the
    // spare margin from where it was searched, but B moved 0.0016 m more since the look.
    b.centre.x() -= 0.0004;
    c.centre.x() += 0.00024;
    list.Update(spheres, none, no_tools, kMargin);
    reference.Detect(spheres, none, no_tools, &expected, kMargin);
    std::set<Key> kept;
    for (const ContactCandidate& cand : list.candidates()) kept.insert(KeyOf(cand));
    for (const ContactCandidate& cand : expected) {
      ASSERT_TRUE(kept.count(KeyOf(cand)))
          << "move " << k << ": B and C within the margin, not listed";
    }
    if (!expected.empty()) return;  // they met, and the list had them
  }
  FAIL() << "B and C never came within the margin: the case was not built";
}

}  // namespace
}  // namespace viscera::collision
