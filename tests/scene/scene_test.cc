#include "scene/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "common/check.h"
#include "mechanics/model.h"
#include "scene/shapes.h"

namespace viscera::scene {
namespace {

const std::string kIntestine = R"(
[contacts]
self = false

[intestine]
length = 2.0
radius = 0.0125
mass = 0.5
control_points = 41
stretch_stiffness = 50.0
[intestine.shape]
kind = "straight"
start = [0.0, 0.0, 1.0]
direction = [1.0, 0.0, 0.0]
)";

// Expects ParseScene(text) to throw an InputError whose message contains every fragment.
void ExpectError(const std::string& text, std::initializer_list<const char*> fragments) {
  try {
    ParseScene(text, "test.toml");
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const InputError& e) {
    const std::string message = e.what();
    for (const char* f : fragments)
      EXPECT_NE(message.find(f), std::string::npos) << "'" << f << "' not in: " << message;
  }
}

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(Scene, ParsesAMinimalSceneWithDefaults) {
  const Scene s = ParseScene(kIntestine);
  EXPECT_EQ(s.model.initial_q.rows(), 41);
  EXPECT_EQ(s.model.rate_hz, 100.0);
  EXPECT_EQ(s.model.integrator, mechanics::IntegratorKind::kRk4);
  EXPECT_EQ(s.model.gravity, Vec3(0.0, 0.0, -9.81));
  EXPECT_TRUE(s.warnings.empty());
  EXPECT_NEAR((s.model.initial_q.row(40) - s.model.initial_q.row(0)).norm(), 2.0, 1e-12);
}

// The server's load estimate (SceneLimits::vet) must time what the session runs: the settled
// pile, not only the falling start.
TEST(Scene, VetSeesTheStartBeforeSettlingAndTheSettledModelAfter) {
  SceneLimits limits;
  std::vector<std::pair<bool, double>> calls;  // (settled, height of the middle point)
  limits.vet = [&](const mechanics::ModelParams& p, bool settled) {
    calls.emplace_back(settled, p.initial_q(20, 2));
  };
  ParseScene("[simulation]\nsettle = 0.2\n" + kIntestine, "test.toml", limits);
  ASSERT_EQ(calls.size(), 2u);
  EXPECT_FALSE(calls[0].first);
  EXPECT_EQ(calls[0].second, 1.0);  // the straight start
  EXPECT_TRUE(calls[1].first);
  EXPECT_LT(calls[1].second, 0.99);  // it fell while settling
  // The settle runs without the linearization guard and with backward Euler (scene.cc, Settle);
  // what runs has both back.
  const Scene settled = ParseScene("[simulation]\nsettle = 0.2\n" + kIntestine);
  EXPECT_TRUE(settled.model.linearization_guard);
  EXPECT_EQ(settled.model.implicit_scheme, mechanics::ImplicitScheme::kBdf2);
  // So the settled start is the same whichever scheme the scene runs.
  const std::string implicit = "[simulation]\nsettle = 0.2\nintegrator = \"implicit\"\n";
  const Scene bdf2 = ParseScene(implicit + kIntestine);
  const Scene euler = ParseScene(implicit + "implicit_scheme = \"backward_euler\"\n" + kIntestine);
  EXPECT_TRUE((bdf2.model.initial_q.array() == euler.model.initial_q.array()).all());
  calls.clear();
  ParseScene(kIntestine, "test.toml", limits);  // no settle: one call, on what runs
  ASSERT_EQ(calls.size(), 1u);
  EXPECT_TRUE(calls[0].first);
}

// The settle's first steps are timed (SceneLimits::vet, before the settle is paid for) as the
// settle runs them: with friction without a static phase, and with the mesentery's slack long
// enough for every tether that the start overstretches (Settle tightens it gradually), not with
// the scene's Coulomb friction and its tethers pulled taut at once.
TEST(Scene, VetTimesTheSettlesStartAsTheSettleRunsIt) {
  // the straight tube 1 m above a root 0.2 m long whose tethers allow 5-12 cm: 0.95 m too far
  const std::string scene =
      "[simulation]\nsettle = 0.05\n" +
      Replace(kIntestine, "self = false\n",
              "self = false\nfriction_law = \"stick_slip\"\nfriction = 0.3\n") +
      R"(
[mesentery]
root_start = [0.0, 0.0, 0.0]
root_end = [2.0, 0.0, 0.0]
lengths = [[0.0, 0.05], [0.5, 0.12], [1.0, 0.05]]
stiffness = 100.0
)";
  std::vector<mechanics::ModelParams> vetted;
  SceneLimits limits;
  limits.vet = [&](const mechanics::ModelParams& p, bool) { vetted.push_back(p); };
  const Scene s = ParseScene(scene, "test.toml", limits);
  ASSERT_EQ(vetted.size(), 2u);
  ASSERT_TRUE(vetted[0].mesentery && vetted[1].mesentery);
  // the farthest tethers, near the ends: 1 m for 5 cm
  EXPECT_GT(vetted[0].mesentery->extra_slack, 0.9);
  EXPECT_LE(vetted[0].mesentery->extra_slack, 1.0 - 0.05 + 1e-9);
  EXPECT_EQ(vetted[0].contacts.friction_law, mechanics::FrictionLaw::kRegularized);
  EXPECT_EQ(vetted[0].rate_hz, 100.0);
  // what runs has the scene's own
  EXPECT_EQ(vetted[1].mesentery->extra_slack, 0.0);
  EXPECT_EQ(vetted[1].contacts.friction_law, mechanics::FrictionLaw::kStickSlip);
  EXPECT_EQ(s.model.mesentery->extra_slack, 0.0);
  EXPECT_EQ(s.model.contacts.friction_law, mechanics::FrictionLaw::kStickSlip);
}

// A start whose centre line lies more than the tube's radius past an obstacle's surface (the
// whole tube on the wrong side) is refused, naming the obstacle, the point and the depth; a tube
// starting in contact, partly inside, is read.
TEST(Scene, AStartDeepInsideAnObstacleIsRefused) {
  // the straight tube runs along x at z = 1, from x = 0 to 2 (41 points, 5 cm apart)
  const auto with = [&](const std::string& obstacle) {
    return kIntestine + "[[obstacle]]\n" + obstacle;
  };
  // a cavity that holds the tube but its last 16 cm (x = 1.84 .. 2): the last point is 14 cm out
  ExpectError(with("name = \"cavity\"\nkind = \"ellipsoid\"\ncentre = [0.93, 0.0, 1.0]\n"
                   "radii = [0.93, 0.2, 0.2]\ninside = true\n"),
              {"test.toml", "intestine.shape", "control point 40 of 41", "outside obstacle",
               "\"cavity\"", "inside = true", "tube's radius (12.5 mm)"});
  // an organ the tube runs through: its centre line 5 cm inside a sphere at x = 1
  ExpectError(with("name = \"liver\"\nkind = \"sphere\"\ncentre = [1.0, 0.0, 1.0]\n"
                   "radius = 0.05\n"),
              {"control point 20 of 41 (s = 0.5)", "50 mm inside obstacle \"liver\""});
  // the same organ lowered so that the tube's surface dips 1 cm into it, its centre line outside:
  // a tube laid in contact is read (the contacts push it out)
  const Scene touching =
      ParseScene(with("kind = \"sphere\"\ncentre = [1.0, 0.0, 0.9375]\nradius = 0.06\n"));
  EXPECT_EQ(touching.model.obstacles.size(), 1u);
  // a centre line inside, but by less than the radius: read (cavity.toml's coil starts 4 mm into
  // the spine)
  ParseScene(with("kind = \"sphere\"\ncentre = [1.0, 0.0, 0.95]\nradius = 0.06\n"));
  // what the check sees: the deepest point and its obstacle
  const Scene tube = ParseScene(kIntestine);
  std::vector<collision::Obstacle> obstacles(2);
  obstacles[1].kind = collision::ObstacleKind::kPlane;  // the floor 3 cm above the tube
  obstacles[1].point = Vec3(0.0, 0.0, 1.03);
  obstacles[0].point = Vec3(0.0, 0.0, -1.0);  // far below
  const StartOverlap o = DeepestStartOverlap(tube.model.initial_q, obstacles);
  EXPECT_EQ(o.obstacle, 1u);
  EXPECT_NEAR(o.depth, 0.03, 1e-12);
  EXPECT_EQ(DeepestStartOverlap(tube.model.initial_q, {obstacles[0]}).point, -1);
}

TEST(Scene, ReadsEverySimulationKey) {
  const Scene s = ParseScene(
      "[simulation]\nrate_hz = 500\nsubsteps = 3\nintegrator = \"implicit\"\n"
      "gravity = [0, -1.62, 0]\nmass_solver = \"cholmod\"\nlinearization_guard = false\n"
      "implicit_scheme = \"backward_euler\"\ncg_iteration_cap = 3\n" +
      kIntestine);
  EXPECT_EQ(s.model.rate_hz, 500.0);
  EXPECT_EQ(s.model.cg_iteration_cap, 3);
  EXPECT_EQ(ParseScene(kIntestine).model.cg_iteration_cap, 0);  // the default: the integrator's 240
  EXPECT_EQ(s.model.implicit_scheme, mechanics::ImplicitScheme::kBackwardEuler);
  EXPECT_EQ(ParseScene(kIntestine).model.implicit_scheme,
            mechanics::ImplicitScheme::kBdf2);  // the default
  EXPECT_FALSE(s.model.linearization_guard);
  EXPECT_TRUE(ParseScene(kIntestine).model.linearization_guard);  // on by default
  EXPECT_EQ(s.model.substeps, 3);
  EXPECT_EQ(s.model.integrator, mechanics::IntegratorKind::kImplicitEuler);
  EXPECT_EQ(s.model.mass_solver, mechanics::MassSolverKind::kCholmod);
  EXPECT_EQ(s.model.gravity, Vec3(0.0, -1.62, 0.0));
}

TEST(Scene, MissingKeysAreNamed) {
  ExpectError(Replace(kIntestine, "length = 2.0\n", ""),
              {"test.toml", "intestine.length", "missing"});
  ExpectError(Replace(kIntestine, "kind = \"straight\"\n", ""),
              {"intestine.shape.kind", "missing"});
  ExpectError("[simulation]\nrate_hz = 100\n", {"[intestine]", "missing"});
}

TEST(Scene, AnIntestineLeftUnsaidIsTheTissueCards) {
  // A tube without stiffness would stretch like a thread under a tool: the keys left out take the
  // measured human small intestine's values, and the mass follows the length.
  std::string scene = kIntestine;
  for (const char* key : {"radius", "mass", "stretch_stiffness", "bend_stiffness"}) {
    const size_t at = scene.find(std::string("\n") + key + " = ");
    if (at != std::string::npos) scene.erase(at + 1, scene.find('\n', at + 1) - at);
  }
  const mechanics::ModelParams p = ParseScene(scene).model;
  EXPECT_EQ(p.radius, mechanics::TissueCard::kRadius);
  EXPECT_DOUBLE_EQ(p.mass, mechanics::TissueCard::kLinearDensity * p.length);
  EXPECT_EQ(p.stretch_stiffness, mechanics::TissueCard::kStretchStiffness);
  EXPECT_EQ(p.bend_stiffness, mechanics::TissueCard::kBendStiffness);
  EXPECT_GT(p.stretch_stiffness, 0.0);
}

TEST(Scene, WrongTypesAreNamedWithTheirValue) {
  ExpectError(Replace(kIntestine, "length = 2.0", "length = \"long\""),
              {"intestine.length", "long", "expected a number"});
  ExpectError(Replace(kIntestine, "control_points = 41", "control_points = 4.5"),
              {"intestine.control_points", "4.5", "integer"});
  ExpectError(Replace(kIntestine, "start = [0.0, 0.0, 1.0]", "start = [0.0, 1.0]"),
              {"intestine.shape.start", "[x, y, z]"});
  ExpectError("[simulation]\nintegrator = \"euler\"\n" + kIntestine,
              {"simulation.integrator", "euler", "rk4"});
  ExpectError("[simulation]\nlinearization_guard = 1\n" + kIntestine,
              {"simulation.linearization_guard"});
  ExpectError("[simulation]\nimplicit_scheme = \"bdf3\"\n" + kIntestine,
              {"simulation.implicit_scheme", "bdf3", "bdf2"});
  // lowered only: a scene may not make its solves dearer than the shipped 240 iterations
  ExpectError("[simulation]\ncg_iteration_cap = 241\n" + kIntestine,
              {"simulation.cg_iteration_cap", "241", "1..240"});
  ExpectError("[simulation]\ncg_iteration_cap = 0\n" + kIntestine,
              {"simulation.cg_iteration_cap", "0", "1..240"});
}

TEST(Scene, NonFiniteAndOutOfRangeValuesAreRejected) {
  ExpectError(Replace(kIntestine, "length = 2.0", "length = nan"),
              {"intestine.length", "nan", "finite"});
  ExpectError(Replace(kIntestine, "mass = 0.5", "mass = inf"), {"intestine.mass", "finite"});
  ExpectError(Replace(kIntestine, "mass = 0.5", "mass = -1"), {"intestine.mass", "-1", "> 0"});
  ExpectError(Replace(kIntestine, "start = [0.0, 0.0, 1.0]", "start = [0.0, nan, 1.0]"),
              {"intestine.shape.start[1]", "finite"});
  ExpectError(Replace(kIntestine, "control_points = 41", "control_points = 3"),
              {"control_points", "3", "at least 4"});
  ExpectError(Replace(kIntestine, "mass = 0.5", "mass = 0.5\npinned = [\"middle\"]"),
              {"intestine.pinned", "middle"});
  ExpectError(Replace(kIntestine, "mass = 0.5", "mass = 0.5\npinned = [1.5]"),
              {"intestine.pinned", "1.5", "[0, 1]"});
}

TEST(Scene, UnknownKeyInKnownTableIsAnError) {
  ExpectError(Replace(kIntestine, "mass = 0.5", "mass = 0.5\nstiffnes = 3"),
              {"intestine.stiffnes", "unknown key"});
  // the line of the typo, and the known key it is nearest to
  ExpectError(Replace(kIntestine, "mass = 0.5", "mass = 0.5\nmas = 3"),
              {"intestine.mas = 3 (line ", "unknown key; did you mean \"mass\"?"});
  ExpectError(Replace(kIntestine, "kind = \"straight\"", "kind = \"straight\"\nradius = 1"),
              {"intestine.shape.radius", "unknown key"});
}

TEST(Scene, UnknownTopLevelTableIsAWarning) {
  const Scene s = ParseScene(kIntestine + "\n[skin]\nmethod = \"parametric\"\n");
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("[skin]"), std::string::npos);
}

TEST(Scene, ObstaclesOfEveryKindAreParsed) {
  const Scene s = ParseScene(kIntestine + R"(
[[obstacle]]
kind = "plane"
point = [0, 0, 0]
normal = [0, 0, 2]
[[obstacle]]
kind = "sphere"
centre = [0, 0, 1.2]
radius = 0.1
[[obstacle]]
kind = "capsule"
a = [0, 0, 0]
b = [0, 0, 0.9]
radius = 0.05
[[obstacle]]
kind = "box"
centre = [1, 0, 0]
half_extents = [0.1, 0.2, 0.3]
orientation = [1, 0, 0, 0]
[[obstacle]]
name = "cavity"
kind = "ellipsoid"
centre = [1, 0, 1]
radii = [1.2, 0.15, 0.1]
inside = true
)");
  ASSERT_EQ(s.model.obstacles.size(), 5u);
  EXPECT_EQ(s.model.obstacles[0].normal, Vec3(0, 0, 1));
  EXPECT_EQ(s.model.obstacles[4].name, "cavity");
  EXPECT_TRUE(s.model.obstacles[4].inside);
  EXPECT_TRUE(s.warnings.empty());
  ExpectError(kIntestine + "\n[[obstacle]]\nkind = \"torus\"\n", {"obstacle[0].kind", "torus"});
  ExpectError(kIntestine + "\n[[obstacle]]\nkind = \"sphere\"\ncentre = [0,0,0]\nradius = -1\n",
              {"obstacle[0].radius", "-1"});
  ExpectError(kIntestine + "\n[[obstacle]]\nkind = \"mesh\"\nfile = \"nope.obj\"\n",
              {"nope.obj", "cannot open"});
}

TEST(Scene, ContactsAndToolsAreParsed) {
  const std::string bare = Replace(kIntestine, "[contacts]\nself = false\n", "");
  EXPECT_TRUE(ParseScene(bare).model.contacts.self);  // on by default in scenes
  const Scene s = ParseScene(bare + R"(
[contacts]
self = false
stiffness = 800
damping = 2
friction = 0.5
[[tool]]
name = "left"
port = [0.1, 0.0, 0.3]
max_force = 4
)");
  EXPECT_FALSE(s.model.contacts.self);
  EXPECT_EQ(s.model.contacts.stiffness, 800.0);
  ASSERT_EQ(s.model.tools.size(), 1u);
  EXPECT_EQ(s.model.tools[0].name, "left");
  EXPECT_EQ(s.model.tools[0].max_force, 4.0);
  ExpectError(
      kIntestine +
          "\n[[tool]]\nname = \"a\"\nport = [0,0,0]\n[[tool]]\nname = \"a\"\nport = [0,0,0]\n",
      {"tool[1].name", "share"});
  ExpectError(bare + "\n[contacts]\nstiffness = 0\n",
              {"contacts.stiffness", "expected 1..100000 N/m"});
}

TEST(Scene, SyntaxErrorsGiveLineAndColumn) {
  ExpectError("[intestine\nlength = 1\n", {"test.toml:1:"});
}

TEST(Scene, ShapesPlaceControlPointsAtEqualArcLength) {
  // With 401 points s = 5 mm apart, a chord is shorter than its arc by (s kappa)^2 / 24 of the
  // spacing: 1e-4 on the helix (kappa = 10 / m), 6.4e-4 at the serpentine's crests
  // (kappa = 25 / m). Allow 1e-3.
  for (const char* shape : {"kind = \"helix\"\ncenter = [0, 0, 0.2]\nradius = 0.1\npitch = 0.03",
                            "kind = \"serpentine\"\namplitude = 0.1\nwavelength = 0.4"}) {
    std::string text =
        Replace(kIntestine,
                "kind = \"straight\"\nstart = [0.0, 0.0, 1.0]\ndirection = [1.0, 0.0, 0.0]", shape);
    text = Replace(text, "control_points = 41", "control_points = 401");
    const Scene s = ParseScene(text);
    const Points& q = s.model.initial_q;
    ASSERT_EQ(q.rows(), 401);
    double total = 0.0;
    for (int i = 0; i + 1 < 401; ++i) {
      const double chord = (q.row(i + 1) - q.row(i)).norm();
      EXPECT_NEAR(chord, 2.0 / 400, 1e-3 * 2.0 / 400) << shape << " " << i;
      total += chord;
    }
    EXPECT_NEAR(total, 2.0, 1e-3) << shape;
  }
}

TEST(Scene, PointsShapeGivesTheControlPointsDirectly) {
  const std::string text = R"(
[intestine]
length = 0.3
radius = 0.01
mass = 0.1
[intestine.shape]
kind = "points"
points = [[0,0,0], [0.1,0,0], [0.2,0,0], [0.3,0,0], [0.3,0.1,0]]
)";
  const Scene s = ParseScene(text);
  EXPECT_EQ(s.model.initial_q.rows(), 5);
  EXPECT_EQ(s.model.initial_q(4, 1), 0.1);
  ExpectError(Replace(text, "mass = 0.1", "mass = 0.1\ncontrol_points = 7"),
              {"intestine.shape.points", "5", "7"});
}

TEST(Scene, AttachmentsArePinnedToTheirCurvePoint) {
  const Scene s = ParseScene(kIntestine +
                             "\n[[attachment]]\nat = 0.0\nstiffness = 200\n"
                             "[[attachment]]\nat = 1.0\npoint = [2, 0, 0.5]\nstiffness = "
                             "100\ndamping = 1\nrest_length = 0.1\n");
  ASSERT_EQ(s.model.attachments.size(), 2u);
  EXPECT_FALSE(s.model.attachments[0].point.has_value());
  EXPECT_EQ(*s.model.attachments[1].point, Vec3(2, 0, 0.5));
  const mechanics::Model model(s.model);
  EXPECT_LT((model.attachments()[0].anchor - Vec3(0, 0, 1)).norm(), 1e-12);
  ExpectError(kIntestine + "\n[[attachment]]\nat = 0.5\n", {"attachment[0].stiffness", "missing"});
}

TEST(Scene, ShippedScenesLoadAndBuildModels) {
  for (const char* name : {"fall", "hanging", "attached"}) {
    const std::string path = std::string(VISCERA_SOURCE_DIR) + "/scenes/" + name + ".toml";
    const Scene s = LoadSceneFile(path);
    EXPECT_NO_THROW(mechanics::Model{s.model}) << path;
  }
  const Scene fall = LoadSceneFile(std::string(VISCERA_SOURCE_DIR) + "/scenes/fall.toml");
  EXPECT_EQ(fall.model.initial_q.rows(), 250);
  EXPECT_EQ(fall.model.length, 4.0);
  EXPECT_GT(fall.model.initial_q.col(2).minCoeff(), 0.05);  // above the surface
}

TEST(Scene, MissingFileIsAClearError) {
  EXPECT_THROW(LoadSceneFile("/nonexistent/scene.toml"), InputError);
}

TEST(Scene, AnotherRateKeepsTheSubStepLengthNotTheCount) {
  mechanics::ModelParams p;
  p.rate_hz = 100.0;
  p.substeps = 2;  // 5 ms sub-steps
  auto at = [&p](double rate) {
    mechanics::ModelParams q = p;
    ChangeRate(&q, rate);
    EXPECT_EQ(q.rate_hz, rate);
    EXPECT_LE(1.0 / (q.rate_hz * q.substeps), 0.005 + 1e-15) << rate << " Hz";
    return q.substeps;
  };
  EXPECT_EQ(at(1000.0), 1);
  EXPECT_EQ(at(200.0), 1);  // exactly 5 ms: no rounding up
  EXPECT_EQ(at(150.0), 2);
  EXPECT_EQ(at(100.0), 2);
  EXPECT_EQ(at(50.0), 4);
  EXPECT_EQ(at(30.0), 7);
}

// [camera]: the laparoscope through its port; without it, no scope (a plain framing camera).
TEST(Scene, ReadsTheLaparoscope) {
  EXPECT_FALSE(ParseScene(kIntestine).model.scope.has_value());
  const Scene s =
      ParseScene(kIntestine + "[camera]\nport = [0, -0.1, 0.3]\nlook_at = [0, 0, 0.1]\n");
  ASSERT_TRUE(s.model.scope.has_value());
  const mechanics::ScopeParams defaults;
  EXPECT_EQ(s.model.scope->port, Vec3(0.0, -0.1, 0.3));
  EXPECT_EQ(s.model.scope->look_at, Vec3(0.0, 0.0, 0.1));
  EXPECT_EQ(s.model.scope->optics_deg, 0.0);
  EXPECT_EQ(s.model.scope->fov_deg, defaults.fov_deg);
  EXPECT_EQ(s.model.scope->light_range, defaults.light_range);
  EXPECT_TRUE(s.warnings.empty());
  const Scene oblique =
      ParseScene(kIntestine +
                 "[camera]\nport = [0, -0.1, 0.3]\ndirection = [0, 0, -2]\noptics = 30\n"
                 "roll = 90\nfov = 80\ninsertion = 0.08\nlight_range = 0.2\nlight_cone = 45\n"
                 "up = [0, 2, 0]\n");
  EXPECT_NEAR((oblique.model.scope->look_at - Vec3(0.0, -0.1, 0.2)).norm(), 0.0, 1e-12)
      << "10 cm along";
  EXPECT_EQ(oblique.model.scope->optics_deg, 30.0);
  EXPECT_EQ(oblique.model.scope->roll_deg, 90.0);
  EXPECT_EQ(oblique.model.scope->fov_deg, 80.0);
  EXPECT_EQ(oblique.model.scope->insertion, 0.08);
  EXPECT_EQ(oblique.model.scope->light_cone_deg, 45.0);
  EXPECT_EQ(oblique.model.scope->up, Vec3(0.0, 1.0, 0.0));
}

TEST(Scene, RefusesABadLaparoscope) {
  const std::string port = kIntestine + "[camera]\nport = [0, -0.1, 0.3]\n";
  ExpectError(port, {"camera.look_at", "one of them"});
  ExpectError(port + "look_at = [0, 0, 0]\ndirection = [0, 0, -1]\n",
              {"camera.look_at", "not both"});
  ExpectError(port + "look_at = [0, -0.1, 0.3]\n", {"camera.look_at", "1 mm"});
  ExpectError(port + "direction = [0, 0, 0]\n", {"camera.direction", "zero"});
  ExpectError(port + "direction = [0, 0, -1]\n", {"camera.up", "shaft"});
  ExpectError(port + "direction = [0, 1, -0.3]\noptics = 75\n", {"camera.optics", "75", "[0, 60]"});
  ExpectError(port + "direction = [0, 1, -0.3]\noptics = 30\nup = [0, 1, 0]\n",
              {"camera.up", "31"});
  ExpectError(port + "direction = [0, 1, -0.3]\nfov = 200\n", {"camera.fov"});
  ExpectError(port + "direction = [0, 1, -0.3]\nlight_range = 0\n", {"camera.light_range"});
  ExpectError(port + "direction = [0, 1, -0.3]\nzoom = 2\n", {"camera.zoom"});
}

}  // namespace
}  // namespace viscera::scene
