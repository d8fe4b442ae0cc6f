#include "render/tessellation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "collision/obstacle.h"

namespace viscera::render {
namespace {

Vec3 V(const Eigen::Vector3f& v) { return v.cast<double>(); }

// Every vertex on the obstacle's surface (|signed distance| < tol), every vertex normal along
// the surface normal, every triangle facing outward.
void ExpectOnSurfaceAndOutward(const collision::Obstacle& o, const TriMesh& mesh, double tol) {
  ASSERT_GT(mesh.num_triangles(), 0);
  for (int i = 0; i < mesh.num_vertices(); ++i) {
    Vec3 normal;
    const double d = collision::SignedDistance(o, V(mesh.positions[i]), &normal);
    EXPECT_NEAR(d, 0.0, tol) << "vertex " << i;
    // a box's vertices are its corners, where the surface normal is not defined
    if (o.kind != collision::ObstacleKind::kBox) {
      EXPECT_GT(normal.dot(V(mesh.normals[i])), 0.99) << "vertex " << i;
    }
    EXPECT_NEAR(mesh.normals[i].norm(), 1.0f, 1e-5f);
  }
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    const Vec3 a = V(mesh.positions[mesh.indices[3 * t]]),
               b = V(mesh.positions[mesh.indices[3 * t + 1]]),
               c = V(mesh.positions[mesh.indices[3 * t + 2]]);
    const Vec3 face = (b - a).cross(c - a);
    if (face.norm() < 1e-12) continue;  // degenerate triangles at the poles
    const Vec3 n = V(mesh.normals[mesh.indices[3 * t]]) + V(mesh.normals[mesh.indices[3 * t + 1]]) +
                   V(mesh.normals[mesh.indices[3 * t + 2]]);
    EXPECT_GT(face.dot(n), 0.0) << "triangle " << t << " faces inward";
  }
}

// Closed: every directed edge (by position, so seams and poles count) has its reverse.
void ExpectClosed(const TriMesh& mesh) {
  // positions rounded to 1 um, so that the coincident vertices of a pole match
  std::map<std::pair<std::tuple<long, long, long>, std::tuple<long, long, long>>, int> edges;
  auto key = [&](uint32_t i) {
    const Eigen::Vector3f& p = mesh.positions[i];
    return std::tuple{std::lround(p.x() * 1e6), std::lround(p.y() * 1e6), std::lround(p.z() * 1e6)};
  };
  for (int t = 0; t < mesh.num_triangles(); ++t) {
    for (int e = 0; e < 3; ++e) {
      const auto a = key(mesh.indices[3 * t + e]), b = key(mesh.indices[3 * t + (e + 1) % 3]);
      if (a != b) ++edges[{a, b}];
    }
  }
  int open = 0;
  for (const auto& [edge, count] : edges)
    open += edges.count({edge.second, edge.first}) == 0 ? 1 : 0;
  EXPECT_EQ(open, 0);
}

TEST(Tessellation, EllipsoidIsOnItsSurfaceOutwardAndClosed) {
  collision::Obstacle o;
  o.kind = collision::ObstacleKind::kEllipsoid;
  o.centre = {0.1, -0.2, 0.3};
  o.radii = {0.2, 0.16, 0.13};
  o.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()));
  TriMesh mesh;
  AppendObstacle(o, Vec3::Zero(), 1.0, &mesh);
  ExpectOnSurfaceAndOutward(o, mesh, 1e-6);
  ExpectClosed(mesh);
}

TEST(Tessellation, CapsuleSphereAndBoxAreOnTheirSurfacesAndOutward) {
  collision::Obstacle capsule;
  capsule.kind = collision::ObstacleKind::kCapsule;
  capsule.a = {-0.15, 0.13, 0.09};
  capsule.b = {0.15, 0.10, 0.12};
  capsule.radius = 0.02;
  collision::Obstacle sphere;
  sphere.kind = collision::ObstacleKind::kSphere;
  sphere.centre = {-0.16, 0.0, 0.04};
  sphere.radius = 0.03;
  collision::Obstacle box;
  box.kind = collision::ObstacleKind::kBox;
  box.centre = {0.0, 0.1, 0.0};
  box.half_extents = {0.05, 0.02, 0.01};
  box.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Vec3::UnitZ()));
  for (const collision::Obstacle& o : {capsule, sphere, box}) {
    TriMesh mesh;
    AppendObstacle(o, Vec3::Zero(), 1.0, &mesh);
    ExpectOnSurfaceAndOutward(o, mesh, 1e-6);
    if (o.kind != collision::ObstacleKind::kBox)
      ExpectClosed(mesh);  // the box's faces are separate
  }
}

TEST(Tessellation, PlaneIsASquareAroundThePointGiven) {
  TriMesh mesh;
  AppendPlane(Vec3(0, 0, 0.01), Vec3::UnitZ(), Vec3(0.3, 0.2, 5.0), 0.5, &mesh);
  ASSERT_EQ(mesh.num_triangles(), 2);
  Eigen::Vector3f mean = Eigen::Vector3f::Zero();
  for (const Eigen::Vector3f& p : mesh.positions) {
    EXPECT_NEAR(p.z(), 0.01f, 1e-6f);
    mean += p / 4.0f;
  }
  EXPECT_TRUE(mean.isApprox(Eigen::Vector3f(0.3f, 0.2f, 0.01f), 1e-5f));
  const Eigen::Vector3f face =
      (mesh.positions[1] - mesh.positions[0]).cross(mesh.positions[2] - mesh.positions[0]);
  EXPECT_GT(face.z(), 0.0f);
}

TEST(Tool, ShaftReachesBackPastThePortAndJawsOpen) {
  const Vec3 port(0.0, 0.0, 0.3), tip(0.0, 0.0, 0.1);
  TriMesh closed, open;
  AppendTool(port, tip, Eigen::Quaterniond::Identity(), 0.0, 0.0025, 0.35, &closed);
  AppendTool(port, tip, Eigen::Quaterniond::Identity(), 1.0, 0.0025, 0.35, &open);
  float top = -1.0f, closed_width = 0.0f, open_width = 0.0f;
  for (const Eigen::Vector3f& p : closed.positions) {
    top = std::max(top, p.z());
    if (p.z() < 0.11f) closed_width = std::max(closed_width, std::abs(p.x()));
  }
  for (const Eigen::Vector3f& p : open.positions) {
    if (p.z() < 0.11f) open_width = std::max(open_width, std::abs(p.x()));
  }
  EXPECT_GT(top, 0.1f + 0.35f - 0.02f);  // the shaft is 0.35 m from about the tip
  EXPECT_GT(open_width, 2.0f * closed_width);
  TriMesh none;
  AppendTool(port, port, Eigen::Quaterniond::Identity(), 1.0, 0.0025, 0.35, &none);
  EXPECT_EQ(none.num_triangles(), 0);
}

}  // namespace
}  // namespace viscera::render
