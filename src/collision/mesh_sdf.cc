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

// Closest point on triangle (a, b, c) to p (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3 ClosestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Solid angle of triangle (a, b, c) seen from p (Van Oosterom & Strackee 1983).
double SolidAngle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 x = a - p, y = b - p, z = c - p;
  const double lx = x.norm(), ly = y.norm(), lz = z.norm();
  const double numerator = x.dot(y.cross(z));
  const double denominator = lx * ly * lz + x.dot(y) * lz + y.dot(z) * lx + z.dot(x) * ly;
  return 2.0 * std::atan2(numerator, denominator);
}

}  // namespace

namespace {

// The vertex index of an OBJ face token ("7", "7/1", "-2//3"), or InputError: std::stoi threw
// std::invalid_argument and std::out_of_range instead (found by fuzz/fuzz_obj_loader).
int FaceIndex(const std::string& token, const std::string& path, int line_no) {
  const std::string digits = token.substr(0, token.find('/'));
  char* end = nullptr;
  errno = 0;
  const long i = std::strtol(digits.c_str(), &end, 10);
  ThrowUnless(!digits.empty() && *end == '\0' && errno == 0 && std::abs(i) < (1L << 30), path, ":", line_no,
              ": malformed face index '", token.substr(0, 40), "'");
  return static_cast<int>(i);
}

}  // namespace

MeshSdf MeshSdf::FromObj(const std::string& path, double scale, const Vec3& offset, int resolution) {
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
      ThrowUnless(static_cast<bool>(s >> p.x() >> p.y() >> p.z()), path, ":", line_no, ": malformed vertex");
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
  for (size_t i = 0; i < v.size(); ++i) vertices.row(static_cast<Eigen::Index>(i)) = v[i].transpose();
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> faces(static_cast<Eigen::Index>(f.size()), 3);
  for (size_t i = 0; i < f.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      ThrowUnless(f[i](a) >= 0 && f[i](a) < static_cast<int>(v.size()), path, ": face ", i, " uses vertex ",
                  f[i](a) + 1, " of ", v.size());
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

MeshSdf::MeshSdf(const Points& vertices, const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>& faces,
                 int resolution)
    : vertices_(vertices), faces_(faces) {
  const Vec3 lo = vertices.colwise().minCoeff().transpose(), hi = vertices.colwise().maxCoeff().transpose();
  cell_ = (hi - lo).maxCoeff() / resolution;
  const double pad = 3.0 * cell_;
  origin_ = lo - Vec3::Constant(pad);
  const Vec3 size = hi - lo + Vec3::Constant(2.0 * pad);
  nx_ = static_cast<int>(std::ceil(size.x() / cell_)) + 1;
  ny_ = static_cast<int>(std::ceil(size.y() / cell_)) + 1;
  nz_ = static_cast<int>(std::ceil(size.z() / cell_)) + 1;
  values_.resize(static_cast<size_t>(nx_) * ny_ * nz_);
  for (int k = 0; k < nz_; ++k) {
    for (int j = 0; j < ny_; ++j) {
      for (int i = 0; i < nx_; ++i) {
        const Vec3 p = origin_ + cell_ * Vec3(i, j, k);
        double best = std::numeric_limits<double>::infinity(), winding = 0.0;
        for (Eigen::Index t = 0; t < faces_.rows(); ++t) {
          const Vec3 a = vertices_.row(faces_(t, 0)), b = vertices_.row(faces_(t, 1)), c = vertices_.row(faces_(t, 2));
          best = std::min(best, (ClosestOnTriangle(p, a, b, c) - p).squaredNorm());
          winding += SolidAngle(p, a, b, c);
        }
        // Winding number ~1 inside a closed, outward-oriented mesh, ~0 outside.
        const bool inside = std::abs(winding) / (4.0 * M_PI) > 0.5;
        values_[(static_cast<size_t>(k) * ny_ + j) * nx_ + i] = (inside ? -1.0 : 1.0) * std::sqrt(best);
      }
    }
  }
}

double MeshSdf::Interpolate(const Vec3& p) const {
  const Vec3 g = (p - origin_) / cell_;
  const int i = std::clamp(static_cast<int>(std::floor(g.x())), 0, nx_ - 2);
  const int j = std::clamp(static_cast<int>(std::floor(g.y())), 0, ny_ - 2);
  const int k = std::clamp(static_cast<int>(std::floor(g.z())), 0, nz_ - 2);
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
  const Vec3 hi = origin_ + cell_ * Vec3(nx_ - 1, ny_ - 1, nz_ - 1);
  const Vec3 clamped = p.cwiseMax(origin_).cwiseMin(hi);
  return Interpolate(clamped) + (p - clamped).norm();
}

double MeshSdf::Distance(const Vec3& p, Vec3* normal) const {
  // Outside the grid box, add the distance to the box (the field is valid on the box surface).
  const Vec3 hi = origin_ + cell_ * Vec3(nx_ - 1, ny_ - 1, nz_ - 1);
  const Vec3 clamped = p.cwiseMax(origin_).cwiseMin(hi);
  const double extra = (p - clamped).norm();
  const double h = 0.5 * cell_;
  Vec3 grad(Interpolate(clamped + Vec3(h, 0, 0)) - Interpolate(clamped - Vec3(h, 0, 0)),
            Interpolate(clamped + Vec3(0, h, 0)) - Interpolate(clamped - Vec3(0, h, 0)),
            Interpolate(clamped + Vec3(0, 0, h)) - Interpolate(clamped - Vec3(0, 0, h)));
  if (extra > 0.0) grad = p - clamped;
  const double n = grad.norm();
  *normal = n > 1e-12 ? Vec3(grad / n) : Vec3::UnitZ();
  return Interpolate(clamped) + extra;
}

}  // namespace viscera::collision
