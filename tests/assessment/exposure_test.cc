// Target exposure on hand-made geometry: a disc on the floor seen from above, a straight tube
// lying over it (0), lifted away (1), half over it (in between, the uncovered share), and the
// rules that make a sample unseen without any tube: facing away, outside the view cone.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "assessment/exposure.h"
#include "assessment/target_samples.h"
#include "collision/sphere_chain.h"
#include "mechanics/step.h"
#include "scene/scene.h"
#include "tests/mechanics/table_scene.h"

namespace viscera::assessment {
namespace {

constexpr double kTube = 0.0125;  // tube radius (m)

mechanics::TargetParams Disc(double radius = 0.01, int samples = 256) {
  mechanics::TargetParams t;
  t.name = "lesion";
  t.centre = Vec3(0.0, 0.0, 0.001);
  t.normal = Vec3::UnitZ();
  t.radius = radius;
  t.samples = samples;
  return t;
}

// The scope 20 cm above the target looking straight down.
View Above() { return {Vec3(0.0, 0.0, 0.2), Vec3::Zero(), Vec3::UnitY(), 70.0, 4.0 / 3.0}; }

// A straight tube along x lying on the floor at lateral offset y (centres every radius).
std::vector<Vec3> TubeAt(double y, double z = kTube) {
  std::vector<Vec3> c;
  for (double x = -0.2; x <= 0.2 + 1e-9; x += kTube) c.emplace_back(x, y, z);
  return c;
}

TEST(Exposure, DiscSamplesCoverTheDiscEvenly) {
  const mechanics::TargetParams t = Disc(0.01, 400);
  const std::vector<Vec3> s = TargetSamples(t);
  ASSERT_EQ(s.size(), 400u);
  // equal area per sample: the share within half the radius is a quarter
  int inner = 0;
  for (const Vec3& p : s) {
    EXPECT_NEAR((p - t.centre).dot(t.normal), 0.0, 1e-15);
    EXPECT_LE((p - t.centre).norm(), t.radius);
    if ((p - t.centre).norm() < 0.5 * t.radius) ++inner;
  }
  EXPECT_EQ(inner, 100);
}

TEST(Exposure, PolygonSamplesLieInsideIt) {
  mechanics::TargetParams t;
  t.polygon = {{0, 0, 0}, {0.02, 0, 0}, {0.02, 0.01, 0}, {0.0, 0.01, 0}};
  t.centre = Vec3(0.01, 0.005, 0.0);
  t.normal = Vec3::UnitZ();
  t.samples = 50;
  const std::vector<Vec3> s = TargetSamples(t);
  EXPECT_NEAR(static_cast<double>(s.size()), 50.0, 10.0);
  for (const Vec3& p : s) {
    EXPECT_TRUE(p.x() > 0 && p.x() < 0.02 && p.y() > 0 && p.y() < 0.01) << p.transpose();
  }
  EXPECT_NEAR(PolygonArea(t.polygon), 2e-4, 1e-15);
  EXPECT_NEAR(PolygonNormal(t.polygon).z(), 1.0, 1e-15);
}

TEST(Exposure, CoveredByALoopIsZeroLiftedAwayIsOne) {
  const ExposureEvaluator e({Disc()}, kTube);
  EXPECT_EQ(e.Evaluate(0, Above(), TubeAt(0.0)).fraction, 0.0);
  EXPECT_EQ(e.Evaluate(0, Above(), TubeAt(0.0, 0.10)).fraction, 0.0)
      << "lifted straight up it still hides it";
  EXPECT_EQ(e.Evaluate(0, Above(), TubeAt(0.08, 0.10)).fraction, 1.0) << "lifted and moved aside";
  EXPECT_EQ(e.Evaluate(0, Above(), {}).fraction, 1.0);
}

TEST(Exposure, HalfCoveredIsTheUncoveredShare) {
  // the tube's side over the disc's centre: a sample is seen when its ray passes the tube's axis
  // (a line along x, so in the y-z plane) at least a radius away; counted independently here
  const ExposureEvaluator e({Disc(0.01, 1024)}, kTube);
  const double y = kTube, eye = 0.2;
  const TargetExposure half = e.Evaluate(0, Above(), TubeAt(y));
  int expected = 0;
  for (const Vec3& p : e.samples(0)) {
    const Eigen::Vector2d ray(p.y(), p.z() - eye);  // from the eye, in the y-z plane
    const Eigen::Vector2d axis(y, kTube - eye);
    const double distance = std::abs(ray.x() * axis.y() - ray.y() * axis.x()) / ray.norm();
    if (distance >= kTube) ++expected;
  }
  EXPECT_EQ(static_cast<int>(std::lround(half.fraction * 1024)), expected);
  EXPECT_GT(half.fraction, 0.3);
  EXPECT_LT(half.fraction, 0.7);
}

TEST(Exposure, SeenFromBehindOrOutsideTheViewIsNotSeen) {
  mechanics::TargetParams back = Disc();
  back.normal = -Vec3::UnitZ();
  const ExposureEvaluator e({Disc(), back}, kTube);
  EXPECT_EQ(e.Evaluate(1, Above(), {}).fraction, 0.0) << "its back faces the scope";
  View away = Above();
  away.look_at = Vec3(0.0, 1.0, 0.2);  // looking horizontally: the floor below is out of view
  away.up = Vec3::UnitZ();
  EXPECT_EQ(e.Evaluate(0, away, {}).fraction, 0.0);
  View narrow = Above();
  narrow.look_at = Vec3(0.2, 0.0, 0.0);  // 45 degrees off: outside a 10 degree cone
  narrow.fov_y_deg = 10.0;
  EXPECT_EQ(e.Evaluate(0, narrow, {}).fraction, 0.0);
  View degenerate = Above();
  degenerate.up = Vec3::UnitZ();  // along the view: no image plane, nothing is seen
  EXPECT_EQ(e.Evaluate(0, degenerate, {}).fraction, 0.0);
}

TEST(Exposure, TheConeCullKeepsEveryCapsuleThatCouldBlock) {
  // a tube crossing the line of sight high up, near the eye, far from the target: it is kept
  // and blocks; tubes far from every ray are culled
  const ExposureEvaluator e({Disc()}, kTube);
  std::vector<Vec3> across;
  for (double x = -0.2; x <= 0.2; x += kTube) across.emplace_back(x, 0.0, 0.15);
  const TargetExposure blocked = e.Evaluate(0, Above(), across);
  EXPECT_EQ(blocked.fraction, 0.0);
  EXPECT_GE(blocked.capsules_tested, 2);
  const TargetExposure far = e.Evaluate(0, Above(), TubeAt(0.15));
  EXPECT_EQ(far.capsules_tested, 0);
  EXPECT_EQ(far.fraction, 1.0);
}

TEST(Exposure, SegmentDistanceMatchesBruteForce) {
  // against a dense sampling of both segments, over a fixed set of configurations
  std::srand(7);
  auto rnd = [] { return static_cast<double>(std::rand()) / RAND_MAX - 0.5; };
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 p0(rnd(), rnd(), rnd()), p1(rnd(), rnd(), rnd()), q0(rnd(), rnd(), rnd());
    const Vec3 q1 =
        trial % 10 == 0 ? Vec3(q0 + 0.3 * (p1 - p0)) : Vec3(rnd(), rnd(), rnd());  // some parallel
    double best = 1e300;
    for (int i = 0; i <= 400; ++i) {
      for (int j = 0; j <= 400; ++j) {
        best = std::min(
            best, (p0 + (p1 - p0) * (i / 400.0) - q0 - (q1 - q0) * (j / 400.0)).squaredNorm());
      }
    }
    EXPECT_LE(SegmentSegmentDistanceSquared(p0, p1, q0, q1), best + 1e-12);
    EXPECT_NEAR(std::sqrt(SegmentSegmentDistanceSquared(p0, p1, q0, q1)), std::sqrt(best), 4e-3);
  }
}

// A loop pulled off a target through the real mechanics: the table scene's tube lies on a
// lesion drawn on the table under its middle; the grasper takes the middle, lifts it 15 cm and
// carries it 15 cm aside. The exposure, every step, starts at 0, ends at 1 and never falls by
// more than one sample.
TEST(Exposure, MonotoneWhileALoopIsPulledOff) {
  const mechanics::Model model(scene::ParseScene(viscera::testing::kTableScene).model);
  mechanics::State state = mechanics::InitialState(model);
  mechanics::Workspace workspace(model);
  mechanics::TargetParams lesion = Disc(0.01, 64);
  lesion.centre = Vec3(0.3, 0.0, 0.001);
  const ExposureEvaluator e({lesion}, model.params().radius);
  const View view{Vec3(0.3, -0.05, 0.3), lesion.centre, Vec3::UnitZ(), 70.0, 4.0 / 3.0};
  collision::SphereChain chain(model.curve(), model.params().length, model.params().radius);
  std::vector<Vec3> centres;
  std::vector<double> series;
  auto measure = [&] {
    chain.Place(state.q);
    centres.clear();
    for (const collision::Sphere& s : chain.spheres()) centres.push_back(s.centre);
    series.push_back(e.Evaluate(0, view, centres).fraction);
  };
  mechanics::ToolTarget target;
  auto move = [&](const Vec3& to, double jaw, double seconds) {
    const Vec3 from = target.tip;
    target.jaw = jaw;
    const int steps = static_cast<int>(std::lround(seconds * model.params().rate_hz));
    for (int k = 1; k <= steps; ++k) {
      target.tip = from + (to - from) * (static_cast<double>(k) / steps);
      mechanics::Step(model, {{}, std::span<const mechanics::ToolTarget>(&target, 1)}, &state,
                      &workspace);
      measure();
    }
  };
  const Vec3 middle(0.3, 0.0, 0.0125);
  target.tip = middle + Vec3(0.0, 0.0, 0.05);
  measure();
  move(middle, 1.0, 0.3);
  move(middle, 0.0, 0.3);                          // grasp
  move(middle + Vec3(0.0, 0.0, 0.15), 0.0, 1.0);   // lift
  move(middle + Vec3(0.0, 0.15, 0.15), 0.0, 1.0);  // aside
  move(middle + Vec3(0.0, 0.15, 0.15), 0.0, 0.5);
  ASSERT_EQ(state.nonfinite_resets, 0);
  ASSERT_TRUE(state.tools[0].grasping) << "the loop was carried, not dropped";
  EXPECT_EQ(series.front(), 0.0);
  EXPECT_EQ(series.back(), 1.0);
  double highest = 0.0, worst_drop = 0.0;
  for (const double x : series) {
    worst_drop = std::max(worst_drop, highest - x);
    highest = std::max(highest, x);
  }
  EXPECT_LE(worst_drop, 1.0 / 64 + 1e-12);
  EXPECT_GT(
      std::count_if(series.begin(), series.end(), [](double x) { return x > 0.0 && x < 1.0; }), 10)
      << "it uncovers gradually: the test sees the way between";
}

}  // namespace
}  // namespace viscera::assessment
