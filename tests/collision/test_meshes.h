#pragma once
// Small procedural meshes for the distance-field tests (vertices #V by 3, triangles #F by 3,
// outward-oriented where closed).
#include <cmath>

#include "collision/triangle_queries.h"

namespace viscera::collision::test {

struct Mesh {
  Points vertices;
  Triangles triangles;
};

// An axis-aligned box [lo, hi], 12 triangles, outward.
inline Mesh Box(const Vec3& lo, const Vec3& hi) {
  Mesh m;
  m.vertices.resize(8, 3);
  for (int i = 0; i < 8; ++i) {
    m.vertices.row(i) << (i & 1 ? hi.x() : lo.x()), (i & 2 ? hi.y() : lo.y()),
        (i & 4 ? hi.z() : lo.z());
  }
  m.triangles.resize(12, 3);
  m.triangles << 0, 2, 3, 0, 3, 1,  // z = lo
      4, 5, 7, 4, 7, 6,             // z = hi
      0, 1, 5, 0, 5, 4,             // y = lo
      2, 6, 7, 2, 7, 3,             // y = hi
      0, 4, 6, 0, 6, 2,             // x = lo
      1, 3, 7, 1, 7, 5;             // x = hi
  return m;
}

// A surface of revolution's grid: n x m quads, two triangles each, vertex (i, j) from `at`.
template <typename At>
Mesh Grid(int n, int m, bool wrap_i, bool wrap_j, At at) {
  const int ni = wrap_i ? n : n + 1, nj = wrap_j ? m : m + 1;
  Mesh mesh;
  mesh.vertices.resize(ni * nj, 3);
  for (int i = 0; i < ni; ++i) {
    for (int j = 0; j < nj; ++j) mesh.vertices.row(i * nj + j) = at(i, j).transpose();
  }
  mesh.triangles.resize(2 * n * m, 3);
  int t = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const int a = i * nj + j, b = ((i + 1) % ni) * nj + j, c = ((i + 1) % ni) * nj + (j + 1) % nj,
                d = i * nj + (j + 1) % nj;
      mesh.triangles.row(t++) << a, b, c;
      mesh.triangles.row(t++) << a, c, d;
    }
  }
  return mesh;
}

// A torus (major radius 1, minor 0.35): closed and not convex, 2 x 32 x 16 triangles.
inline Mesh Torus() {
  return Grid(32, 16, true, true, [](int i, int j) {
    const double u = 2 * M_PI * i / 32, v = 2 * M_PI * j / 16;
    return Vec3((1 + 0.35 * std::cos(v)) * std::cos(u), (1 + 0.35 * std::cos(v)) * std::sin(u),
                0.35 * std::sin(v));
  });
}

// An open, wavy sheet 1 x 1 (2 x 16 x 16 triangles): its winding number crosses 1/2 near it.
inline Mesh WavySheet() {
  return Grid(16, 16, false, false, [](int i, int j) {
    const double x = i / 16.0, y = j / 16.0;
    return Vec3(x, y, 0.08 * std::sin(2 * M_PI * x) * std::cos(M_PI * y));
  });
}

}  // namespace viscera::collision::test
