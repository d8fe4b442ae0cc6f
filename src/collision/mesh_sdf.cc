#include "collision/mesh_sdf.h"

#include <cerrno>
#include <cstdlib>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "common/check.h"

namespace viscera::collision {
namespace {

// The vertex index of an OBJ face token ("7", "7/1", "-2//3"), or InputError: std::stoi threw
// std::invalid_argument and std::out_of_range instead (found by fuzz/fuzz_obj_loader).
int FaceIndex(const std::string& token, const std::string& path, int line_no) {
  const std::string digits = token.substr(0, token.find('/'));
  char* end = nullptr;
  errno = 0;
  const long i = std::strtol(digits.c_str(), &end, 10);
  ThrowUnless(!digits.empty() && *end == '\0' && errno == 0 && std::abs(i) < (1L << 30), path, ":",
              line_no, ": malformed face index '", token.substr(0, 40), "'");
  return static_cast<int>(i);
}

}  // namespace

MeshSdf MeshSdf::FromObj(const std::string& path, double scale, const Vec3& offset,
                         int resolution) {
  std::ifstream in(path);
  ThrowUnless(in.good(), path, ": cannot open mesh");
  std::vector<Vec3> v;
  std::vector<Eigen::Vector3i> f;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v") {
      Vec3 p;
      ThrowUnless(static_cast<bool>(s >> p.x() >> p.y() >> p.z()), path, ":", line_no,
                  ": malformed vertex");
      v.push_back(scale * p + offset);
    } else if (tag == "f") {
      std::vector<int> idx;
      for (std::string token; s >> token;) {
        const int i = FaceIndex(token, path, line_no);
        idx.push_back(i > 0 ? i - 1 : static_cast<int>(v.size()) + i);
      }
      ThrowUnless(idx.size() >= 3, path, ":", line_no, ": a face needs 3 vertices");
      for (size_t k = 1; k + 1 < idx.size(); ++k) f.emplace_back(idx[0], idx[k], idx[k + 1]);
    }
  }
  ThrowUnless(!v.empty() && !f.empty(), path, ": no triangles");
  Points vertices(static_cast<Eigen::Index>(v.size()), 3);
  for (size_t i = 0; i < v.size(); ++i)
    vertices.row(static_cast<Eigen::Index>(i)) = v[i].transpose();
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> faces(static_cast<Eigen::Index>(f.size()),
                                                               3);
  for (size_t i = 0; i < f.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      ThrowUnless(f[i](a) >= 0 && f[i](a) < static_cast<int>(v.size()), path, ": face ", i,
                  " uses vertex ", f[i](a) + 1, " of ", v.size());
    }
    faces.row(static_cast<Eigen::Index>(i)) = f[i].transpose();
  }
  // The grid's cell is the box's largest side over the resolution: a flat-to-a-point or
  // non-finite box has none (the fuzzer's "v 0 0 0 / v 0 0 0 / f 1 2 1" made the grid NaN wide).
  ThrowUnless(vertices.allFinite(), path, ": a vertex is not finite");
  const double extent = (vertices.colwise().maxCoeff() - vertices.colwise().minCoeff()).maxCoeff();
  ThrowUnless(extent > 0.0, path, ": every vertex is at the same point");
  return MeshSdf(vertices, faces, resolution);
}

MeshSdf::MeshSdf(const Points& vertices,
                 const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>& faces,
                 int resolution)
    : vertices_(vertices),
      faces_(faces),
      grid_(GridAround(vertices, resolution)),
      values_(SampleWithHierarchy(vertices_, faces_, grid_)) {}

double MeshSdf::Interpolate(const Vec3& p) const {
  const Vec3 g = (p - grid_.origin) / grid_.cell;
  const int i = std::clamp(static_cast<int>(std::floor(g.x())), 0, grid_.nx - 2);
  const int j = std::clamp(static_cast<int>(std::floor(g.y())), 0, grid_.ny - 2);
  const int k = std::clamp(static_cast<int>(std::floor(g.z())), 0, grid_.nz - 2);
  const double fx = std::clamp(g.x() - i, 0.0, 1.0), fy = std::clamp(g.y() - j, 0.0, 1.0),
               fz = std::clamp(g.z() - k, 0.0, 1.0);
  auto lerp = [](double a, double b, double t) { return a + t * (b - a); };
  const double c00 = lerp(Sample(i, j, k), Sample(i + 1, j, k), fx);
  const double c10 = lerp(Sample(i, j + 1, k), Sample(i + 1, j + 1, k), fx);
  const double c01 = lerp(Sample(i, j, k + 1), Sample(i + 1, j, k + 1), fx);
  const double c11 = lerp(Sample(i, j + 1, k + 1), Sample(i + 1, j + 1, k + 1), fx);
  return lerp(lerp(c00, c10, fy), lerp(c01, c11, fy), fz);
}

double MeshSdf::Distance(const Vec3& p) const {
  const Vec3 hi = grid_.Point(grid_.nx - 1, grid_.ny - 1, grid_.nz - 1);
  const Vec3 clamped = p.cwiseMax(grid_.origin).cwiseMin(hi);
  return Interpolate(clamped) + (p - clamped).norm();
}

double MeshSdf::Distance(const Vec3& p, Vec3* normal) const {
  // Outside the grid box, add the distance to the box (the field is valid on the box surface).
  const Vec3 hi = grid_.Point(grid_.nx - 1, grid_.ny - 1, grid_.nz - 1);
  const Vec3 clamped = p.cwiseMax(grid_.origin).cwiseMin(hi);
  const double extra = (p - clamped).norm();
  const double h = 0.5 * grid_.cell;
  Vec3 grad(Interpolate(clamped + Vec3(h, 0, 0)) - Interpolate(clamped - Vec3(h, 0, 0)),
            Interpolate(clamped + Vec3(0, h, 0)) - Interpolate(clamped - Vec3(0, h, 0)),
            Interpolate(clamped + Vec3(0, 0, h)) - Interpolate(clamped - Vec3(0, 0, h)));
  if (extra > 0.0) grad = p - clamped;
  const double n = grad.norm();
  *normal = n > 1e-12 ? Vec3(grad / n) : Vec3::UnitZ();
  return Interpolate(clamped) + extra;
}

}  // namespace viscera::collision
