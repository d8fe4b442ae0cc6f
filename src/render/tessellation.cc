#include "render/tessellation.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/check.h"

namespace viscera::render {
namespace {

constexpr double kPi = std::numbers::pi;

uint32_t Base(const TriMesh& out) { return static_cast<uint32_t>(out.positions.size()); }

void Push(TriMesh* out, const Vec3& p, const Vec3& n) {
  out->positions.push_back(p.cast<float>());
  out->normals.push_back(n.normalized().cast<float>());
}

// Triangles of a grid of `rings` rings of `slices` vertices from `base`, closed around each
// ring. Going around a ring turns counter-clockwise about the axis from ring 0 to the last,
// so (k, j) -> (k, j + 1) -> (k + 1, j + 1) is counter-clockwise seen from outside.
void GridTriangles(uint32_t base, int rings, int slices, TriMesh* out) {
  const auto at = [&](int k, int j) {
    return base + static_cast<uint32_t>(k * slices + (j % slices));
  };
  for (int k = 0; k + 1 < rings; ++k) {
    for (int j = 0; j < slices; ++j) {
      out->indices.insert(out->indices.end(), {at(k, j), at(k, j + 1), at(k + 1, j + 1)});
      out->indices.insert(out->indices.end(), {at(k, j), at(k + 1, j + 1), at(k + 1, j)});
    }
  }
}

// A right-handed frame (u, v, w) with w along `axis`.
void Frame(const Vec3& axis, Vec3* u, Vec3* v) {
  const Vec3 w = axis.normalized();
  const Vec3 helper = std::abs(w.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  *u = helper.cross(w).normalized();
  *v = w.cross(*u);
}

}  // namespace

void AppendEllipsoid(const Vec3& centre, const Vec3& radii, const Eigen::Quaterniond& rotation,
                     int slices, int stacks, TriMesh* out) {
  VISCERA_DEMAND(slices >= 3 && stacks >= 2 && radii.minCoeff() > 0.0);
  const Mat3 r = rotation.normalized().toRotationMatrix();
  const uint32_t base = Base(*out);
  for (int k = 0; k <= stacks; ++k) {
    const double phi = -0.5 * kPi + kPi * k / stacks;
    for (int j = 0; j < slices; ++j) {
      const double theta = 2.0 * kPi * j / slices;
      const Vec3 u(std::cos(phi) * std::cos(theta), std::cos(phi) * std::sin(theta), std::sin(phi));
      // the normal of an ellipsoid at diag(radii) u is diag(1 / radii) u
      Push(out, centre + r * radii.cwiseProduct(u), r * u.cwiseQuotient(radii));
    }
  }
  GridTriangles(base, stacks + 1, slices, out);
}

void AppendSphere(const Vec3& centre, double radius, int slices, int stacks, TriMesh* out) {
  AppendEllipsoid(centre, Vec3::Constant(radius), Eigen::Quaterniond::Identity(), slices, stacks,
                  out);
}

void AppendCapsule(const Vec3& a, const Vec3& b, double radius, int slices, TriMesh* out) {
  VISCERA_DEMAND(slices >= 4 && radius > 0.0);
  const Vec3 axis = (b - a).norm() > 1e-12 ? Vec3(b - a) : Vec3(Vec3::UnitZ());
  Vec3 u, v;
  Frame(axis, &u, &v);
  const Vec3 w = u.cross(v);
  const int half = std::max(2, slices / 4);  // rings per hemisphere, pole to equator
  const uint32_t base = Base(*out);
  // rings from a's pole to a's equator, then b's equator to b's pole: the cylinder is the
  // band between the two equators
  for (int k = 0; k <= 2 * half + 1; ++k) {
    const bool at_b = k > half;
    const double phi = at_b ? 0.5 * kPi * (k - half - 1) / half : -0.5 * kPi + 0.5 * kPi * k / half;
    const Vec3& c = at_b ? b : a;
    for (int j = 0; j < slices; ++j) {
      const double theta = 2.0 * kPi * j / slices;
      const Vec3 n =
          std::cos(phi) * (std::cos(theta) * u + std::sin(theta) * v) + std::sin(phi) * w;
      Push(out, c + radius * n, n);
    }
  }
  GridTriangles(base, 2 * half + 2, slices, out);
}

void AppendBox(const Vec3& centre, const Vec3& half, const Eigen::Quaterniond& rotation,
               TriMesh* out) {
  const Mat3 r = rotation.normalized().toRotationMatrix();
  for (int axis = 0; axis < 3; ++axis) {
    for (const double sign : {-1.0, 1.0}) {
      // face normal n, and two in-face directions s, t with s x t = n
      const Vec3 n = sign * Vec3::Unit(axis);
      const Vec3 s = sign * Vec3::Unit((axis + 1) % 3);
      const Vec3 t = Vec3::Unit((axis + 2) % 3);
      const uint32_t base = Base(*out);
      for (const auto& [i, j] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
        const Vec3 local =
            n.cwiseProduct(half) + i * s.cwiseProduct(half) + j * t.cwiseProduct(half);
        Push(out, centre + r * local, r * n);
      }
      out->indices.insert(out->indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
  }
}

void AppendPlane(const Vec3& point, const Vec3& normal, const Vec3& around, double half_size,
                 TriMesh* out) {
  const Vec3 n = normal.normalized();
  Vec3 u, v;
  Frame(n, &u, &v);
  const Vec3 centre = around - n.dot(around - point) * n;
  const uint32_t base = Base(*out);
  for (const auto& [i, j] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
    Push(out, centre + half_size * (i * u + j * v), n);
  }
  out->indices.insert(out->indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

void AppendTriangles(const Points& vertices,
                     const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>& faces,
                     TriMesh* out) {
  // area-weighted normals: each face adds its unnormalized cross product to its corners
  Points normals = Points::Zero(vertices.rows(), 3);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Vec3 a = vertices.row(faces(f, 0)), b = vertices.row(faces(f, 1)),
               c = vertices.row(faces(f, 2));
    const Vec3 n = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) normals.row(faces(f, k)) += n.transpose();
  }
  const uint32_t base = Base(*out);
  for (Eigen::Index i = 0; i < vertices.rows(); ++i) Push(out, vertices.row(i), normals.row(i));
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) out->indices.push_back(base + static_cast<uint32_t>(faces(f, k)));
  }
}

void AppendObstacle(const collision::Obstacle& o, const Vec3& around, double plane_half_size,
                    TriMesh* out) {
  using collision::ObstacleKind;
  switch (o.kind) {
    case ObstacleKind::kPlane: AppendPlane(o.point, o.normal, around, plane_half_size, out); break;
    case ObstacleKind::kSphere: AppendSphere(o.centre, o.radius, 48, 24, out); break;
    case ObstacleKind::kCapsule: AppendCapsule(o.a, o.b, o.radius, 32, out); break;
    case ObstacleKind::kBox: AppendBox(o.centre, o.half_extents, o.orientation, out); break;
    case ObstacleKind::kEllipsoid:
      AppendEllipsoid(o.centre, o.radii, o.orientation, 72, 48, out);
      break;
    case ObstacleKind::kMesh:
      ThrowUnless(o.sdf != nullptr, "obstacle \"", o.name, "\": a mesh obstacle without its mesh");
      AppendTriangles(o.sdf->vertices(), o.sdf->faces(), out);
      break;
  }
}

void AppendTool(const Vec3& port, const Vec3& tip, const Eigen::Quaterniond& orientation,
                double jaw, double radius, double shaft_length, TriMesh* out) {
  const double reach = (tip - port).norm();
  if (reach < 1e-6) return;
  const Vec3 axis = (tip - port) / reach;  // along the shaft, toward the tip
  // jaws: two tapered capsules hinged behind the tip, the grasp point between them
  const double jaw_length = 6.0 * radius;
  const Vec3 hinge = tip - 0.7 * jaw_length * axis;
  const Vec3 back = hinge - std::max(shaft_length, (hinge - port).norm()) * axis;
  AppendCapsule(back, hinge, radius, 16, out);
  Vec3 side = orientation.normalized() * Vec3::UnitX();
  side -= side.dot(axis) * axis;
  if (side.norm() < 1e-6) {
    Vec3 unused;
    Frame(axis, &side, &unused);
  }
  side.normalize();
  const double angle = std::clamp(jaw, 0.0, 1.0) * 35.0 * kPi / 180.0 + 0.04;
  for (const double sign : {-1.0, 1.0}) {
    const Vec3 dir = std::cos(angle) * axis + sign * std::sin(angle) * side;
    AppendCapsule(hinge + 0.3 * radius * sign * side, hinge + jaw_length * dir, 0.55 * radius, 12,
                  out);
  }
}

void AppendSkin(const skin::Mesh& mesh, double length, double radius, TriMesh* out) {
  const uint32_t base = Base(*out);
  // texture space: the tube unrolled straight, (along, around) on a cylinder of its radius, so
  // the pattern rides on the tissue; a skin without surface coordinates: the world positions
  const bool on_tissue = mesh.surface.size() == mesh.positions.size();
  out->texture.resize(out->positions.size(), Eigen::Vector3f::Zero());
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    out->positions.push_back(mesh.positions[i].cast<float>());
    out->normals.push_back(mesh.normals[i].cast<float>());
    if (on_tissue) {
      const Eigen::Vector2d& sa = mesh.surface[i];
      out->texture.emplace_back(static_cast<float>(sa.x() * length),
                                static_cast<float>(radius * std::cos(sa.y())),
                                static_cast<float>(radius * std::sin(sa.y())));
    } else {
      out->texture.push_back(out->positions.back());
    }
  }
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) out->indices.push_back(base + static_cast<uint32_t>(t[k]));
  }
}

void AppendRuledFilm(std::span<const Vec3> a, std::span<const Vec3> b, double along_length,
                     double across_length, TriMesh* out) {
  const size_t k = std::min(a.size(), b.size());
  if (k < 2) return;
  const uint32_t base = static_cast<uint32_t>(out->positions.size());
  out->texture.resize(out->positions.size(), Eigen::Vector3f::Zero());
  for (size_t i = 0; i < k; ++i) {
    // across the film: along the root times toward the bowel
    const Vec3 along = a[std::min(i + 1, k - 1)] - a[i > 0 ? i - 1 : 0];
    Vec3 n = along.cross(b[i] - a[i]);
    n = n.norm() > 1e-12 ? Vec3(n.normalized()) : Vec3(Vec3::UnitZ());
    const float x =
        static_cast<float>(along_length * static_cast<double>(i) / static_cast<double>(k - 1));
    out->positions.push_back(a[i].cast<float>());
    out->positions.push_back(b[i].cast<float>());
    out->normals.insert(out->normals.end(), 2, n.cast<float>());
    out->texture.emplace_back(x, 0.0f, 0.0f);
    out->texture.emplace_back(x, static_cast<float>(across_length), 0.0f);
  }
  for (uint32_t i = 0; i + 1 < k; ++i) {
    const uint32_t a0 = base + 2 * i, b0 = a0 + 1, a1 = a0 + 2, b1 = a0 + 3;
    out->indices.insert(out->indices.end(), {a0, a1, b1, a0, b1, b0});
  }
}

}  // namespace viscera::render
