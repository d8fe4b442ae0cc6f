#include "collision/obstacle.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <random>
#include <vector>

#include "common/check.h"

namespace viscera::collision {
namespace {

double D(const Obstacle& o, const Vec3& p, Vec3* n = nullptr) {
  Vec3 normal;
  const double d = SignedDistance(o, p, &normal);
  if (n) *n = normal;
  return d;
}

TEST(Obstacle, PlaneSphereCapsuleBox) {
  Obstacle plane;
  plane.normal = Vec3::UnitZ();
  Vec3 n;
  EXPECT_DOUBLE_EQ(D(plane, Vec3(3, 4, 0.2), &n), 0.2);
  EXPECT_EQ(n, Vec3::UnitZ());

  Obstacle sphere;
  sphere.kind = ObstacleKind::kSphere;
  sphere.centre = Vec3(1, 0, 0);
  sphere.radius = 0.5;
  EXPECT_NEAR(D(sphere, Vec3(1, 2, 0), &n), 1.5, 1e-15);
  EXPECT_TRUE(n.isApprox(Vec3::UnitY()));
  EXPECT_NEAR(D(sphere, Vec3(1.1, 0, 0)), -0.4, 1e-15);

  Obstacle capsule;
  capsule.kind = ObstacleKind::kCapsule;
  capsule.a = Vec3(0, 0, 0);
  capsule.b = Vec3(0, 0, 1);
  capsule.radius = 0.1;
  EXPECT_NEAR(D(capsule, Vec3(0.5, 0, 0.5)), 0.4, 1e-15);
  EXPECT_NEAR(D(capsule, Vec3(0, 0, 1.5)), 0.4, 1e-15);

  Obstacle box;
  box.kind = ObstacleKind::kBox;
  box.half_extents = Vec3(1, 2, 3);
  EXPECT_NEAR(D(box, Vec3(2, 0, 0), &n), 1.0, 1e-15);
  EXPECT_TRUE(n.isApprox(Vec3::UnitX()));
  EXPECT_NEAR(D(box, Vec3(2, 3, 0)), std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(D(box, Vec3(0, 1.5, 0), &n), -0.5, 1e-15);
  EXPECT_TRUE(n.isApprox(Vec3::UnitY()));
  box.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()));
  EXPECT_NEAR(D(box, Vec3(0, 2, 0)), 1.0, 1e-12);  // the x half-extent now points along y
}

TEST(Obstacle, EllipsoidIsExactOnItsSurfaceAndSignedInside) {
  Obstacle e;
  e.kind = ObstacleKind::kEllipsoid;
  e.radii = Vec3(0.3, 0.2, 0.1);
  for (double a = 0.0; a < 2 * M_PI; a += 0.3) {
    const Vec3 on(0.3 * std::cos(a), 0.2 * std::sin(a), 0.0);
    EXPECT_NEAR(D(e, on), 0.0, 1e-12);
  }
  EXPECT_LT(D(e, Vec3(0.1, 0, 0)), 0.0);
  EXPECT_NEAR(D(e, Vec3(0, 0, 0.15)), 0.05, 1e-12);  // along a principal axis it is exact
}

// The ellipsoid's distance as main computed it before PreparedObstacle (its frame built at every
// query): the prepared one must give these bits.
double EllipsoidAsBefore(const Obstacle& o, const Vec3& p, Vec3* normal) {
  const Mat3 r = o.orientation.toRotationMatrix();
  const Vec3 local = r.transpose() * (p - o.centre);
  const Vec3 inv_radii = o.radii.cwiseInverse();
  const Vec3 scaled = local.cwiseProduct(inv_radii);
  const Vec3 grad = scaled.cwiseProduct(inv_radii);
  const double k0 = scaled.norm(), k1 = grad.norm();
  const double inv_k1 = 1.0 / k1;
  *normal = k1 > 1e-12 ? Vec3(r * (grad * inv_k1)) : Vec3(r * Vec3::UnitZ());
  const double d = k1 < 1e-12 ? -o.radii.minCoeff() : k0 * (k0 - 1.0) * inv_k1;
  if (!o.inside) return d;
  *normal = -*normal;
  return -d;
}

// The box's distance as main computed it before PreparedObstacle, likewise.
double BoxAsBefore(const Obstacle& o, const Vec3& p, Vec3* normal) {
  const Mat3 r = o.orientation.toRotationMatrix();
  const Vec3 local = r.transpose() * (p - o.centre);
  const Vec3 q = local.cwiseAbs() - o.half_extents;
  double d;
  if (q.maxCoeff() > 0.0) {
    const Vec3 outside = q.cwiseMax(0.0);
    const Vec3 n_local = outside.cwiseProduct(local.cwiseSign());
    const double n = n_local.norm();
    *normal = r * (n > 1e-12 ? Vec3(n_local * (1.0 / n)) : Vec3::UnitZ());
    d = outside.norm();
  } else {
    int axis;
    d = q.maxCoeff(&axis);
    Vec3 n_local = Vec3::Zero();
    n_local(axis) = local(axis) >= 0.0 ? 1.0 : -1.0;
    *normal = r * n_local;
  }
  if (!o.inside) return d;
  *normal = -*normal;
  return -d;
}

TEST(Obstacle, APreparedObstacleGivesThePlainQuerysBitsForEveryKind) {
  const Eigen::Quaterniond turned(Eigen::AngleAxisd(0.7, Vec3(1, -2, 0.5).normalized()));
  std::vector<Obstacle> all(5);
  all[0].normal = Vec3(0.3, 0.1, 1).normalized();
  all[0].point = Vec3(0.01, 0, -0.02);
  all[1].kind = ObstacleKind::kSphere;
  all[1].centre = Vec3(0.02, -0.01, 0.03);
  all[1].radius = 0.07;
  all[2].kind = ObstacleKind::kCapsule;
  all[2].a = Vec3(-0.1, 0.02, 0);
  all[2].b = Vec3(0.1, -0.03, 0.02);
  all[2].radius = 0.02;
  all[3].kind = ObstacleKind::kBox;
  all[3].centre = Vec3(0.01, 0.02, -0.01);
  all[3].half_extents = Vec3(0.05, 0.08, 0.03);
  all[3].orientation = turned;
  all[4].kind = ObstacleKind::kEllipsoid;
  all[4].centre = Vec3(0, 0, 0.13);
  all[4].radii = Vec3(0.20, 0.16, 0.13);
  all[4].orientation = turned;
  std::mt19937 rng(10);
  std::uniform_real_distribution<double> u(-0.25, 0.25);
  int compared = 0;
  for (bool inside : {false, true}) {
    for (Obstacle o : all) {
      o.inside = inside;
      const PreparedObstacle prepared(o);
      for (int i = 0; i < 2000; ++i) {
        const Vec3 p = all[4].centre + Vec3(u(rng), u(rng), u(rng));
        Vec3 n_plain, n_prepared;
        const double plain = SignedDistance(o, p, &n_plain);
        const double d = prepared.SignedDistance(p, &n_prepared);
        ASSERT_EQ(std::bit_cast<uint64_t>(d), std::bit_cast<uint64_t>(plain))
            << static_cast<int>(o.kind) << " " << i;
        for (int k = 0; k < 3; ++k)
          ASSERT_EQ(std::bit_cast<uint64_t>(n_prepared(k)), std::bit_cast<uint64_t>(n_plain(k)));
        if (o.kind == ObstacleKind::kEllipsoid || o.kind == ObstacleKind::kBox) {
          Vec3 n_before;
          const double before = o.kind == ObstacleKind::kBox ? BoxAsBefore(o, p, &n_before)
                                                             : EllipsoidAsBefore(o, p, &n_before);
          ASSERT_EQ(std::bit_cast<uint64_t>(d), std::bit_cast<uint64_t>(before)) << i;
          for (int k = 0; k < 3; ++k)
            ASSERT_EQ(std::bit_cast<uint64_t>(n_prepared(k)), std::bit_cast<uint64_t>(n_before(k)));
        }
        ++compared;
      }
    }
  }
  EXPECT_EQ(compared, 2 * 5 * 2000);
  // The prepared copy is the obstacle's: moving the original afterwards changes neither.
  Obstacle moved = all[4];
  const PreparedObstacle prepared(moved);
  moved.centre += Vec3(0.05, 0, 0);
  EXPECT_EQ(prepared.obstacle().centre, all[4].centre);
  Vec3 n;
  EXPECT_NE(prepared.SignedDistance(Vec3(0.19, 0, 0.13), &n),
            SignedDistance(moved, Vec3(0.19, 0, 0.13), &n));
}

TEST(Obstacle, InsideFlipsTheSideOfFreeSpace) {
  Obstacle cavity;
  cavity.kind = ObstacleKind::kSphere;
  cavity.radius = 1.0;
  cavity.inside = true;
  Vec3 n;
  EXPECT_NEAR(D(cavity, Vec3(0.25, 0, 0), &n), 0.75, 1e-15);
  EXPECT_TRUE(n.isApprox(-Vec3::UnitX()));  // toward the centre: into free space
  EXPECT_LT(D(cavity, Vec3(1.5, 0, 0)), 0.0);
}

TEST(Obstacle, MeshSdfOfAnOctahedronMatchesItsExactDistance) {
  // The octahedron |x| + |y| + |z| <= 1: signed distance (|x|+|y|+|z| - 1) / sqrt(3) near faces.
  const std::string path = testing::TempDir() + "octahedron.obj";
  std::ofstream(path) << "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
                         "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n";
  Obstacle mesh;
  mesh.kind = ObstacleKind::kMesh;
  mesh.sdf = std::make_shared<MeshSdf>(MeshSdf::FromObj(path, 1.0, Vec3::Zero(), 48));
  Vec3 n;
  for (double s : {0.2, 0.3, 0.4}) {
    const Vec3 p = Vec3::Constant(s);  // along the face normal (1,1,1)
    const double exact = (3 * s - 1) / std::sqrt(3.0);
    EXPECT_NEAR(D(mesh, p, &n), exact, 0.02) << s;
    EXPECT_GT(n.dot(Vec3::Ones().normalized()), 0.95);
  }
  EXPECT_LT(D(mesh, Vec3::Zero()), -0.5);          // deep inside: -1/sqrt(3)
  EXPECT_NEAR(D(mesh, Vec3(3, 0, 0)), 2.0, 0.05);  // outside the grid box: distance grows on
  EXPECT_THROW(MeshSdf::FromObj("/nonexistent.obj", 1.0, Vec3::Zero()), InputError);
}

TEST(Obstacle, AMeshWithNoExtentOrANonFiniteVertexIsRefusedSayingWhy) {
  // Found by fuzz_obj_loader: every vertex at one point gave a grid cell of 0 and a NaN size.
  const auto refused = [](const std::string& name, const std::string& text, double scale,
                          const std::string& why) {
    const std::string path = testing::TempDir() + name;
    std::ofstream(path) << text;
    try {
      MeshSdf::FromObj(path, scale, Vec3::Zero(), 8);
      ADD_FAILURE() << name << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  };
  refused("point.obj", "v 1 2 3\nv 1 2 3\nv 1 2 3\nf 1 2 3\n", 1.0,
          "every vertex is at the same point");
  refused("flat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", 0.0,
          "every vertex is at the same point");
  refused("huge.obj", "v 1e308 0 0\nv -1e308 0 0\nv 0 1 0\nf 1 2 3\n", 10.0, "not finite");
}

}  // namespace
}  // namespace viscera::collision
