#pragma once
/// Geometric checks of skin meshes for the tests. CheckTopology (src/skin/mesh.h) reads
/// indices only, so a ring-built skin passes it whatever its vertex positions; these look
/// at where the triangles are:
///  - SelfIntersections: pairs of triangles that cross, ignoring neighbours (a fold, or two
///    loops of the tube passing through each other, gives many; a good skin gives none);
///  - BadVertexFans: vertices whose triangles do not form one closed fan (vertex manifold).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <queue>
#include <set>
#include <unordered_map>
#include <vector>

#include "skin/mesh.h"

namespace viscera::skin::testing {

namespace internal {

/// Does the segment p-q cross triangle a, b, c (Möller–Trumbore, strictly inside both)?
inline bool SegmentCrossesTriangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                                   const Vec3& c) {
  const Vec3 d = q - p, e1 = b - a, e2 = c - a;
  const Vec3 h = d.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-30) return false;  // parallel (coplanar pairs are ignored)
  const double inv = 1.0 / det;
  const Vec3 s = p - a;
  const double u = inv * s.dot(h);
  if (u <= 0.0 || u >= 1.0) return false;
  const Vec3 qv = s.cross(e1);
  const double v = inv * d.dot(qv);
  if (v <= 0.0 || u + v >= 1.0) return false;
  const double t = inv * e2.dot(qv);
  return t > 0.0 && t < 1.0;
}

inline bool TrianglesCross(const std::array<Vec3, 3>& x, const std::array<Vec3, 3>& y) {
  for (int i = 0; i < 3; ++i) {
    if (SegmentCrossesTriangle(x[i], x[(i + 1) % 3], y[0], y[1], y[2])) return true;
    if (SegmentCrossesTriangle(y[i], y[(i + 1) % 3], x[0], x[1], x[2])) return true;
  }
  return false;
}

}  // namespace internal

/// Number of triangle pairs that cross each other, over pairs whose vertices are more than
/// `neighbourhood` edges apart (so adjacent triangles, which share vertices or edges, and
/// the triangles next to them do not count). Uniform grid over triangle bounding boxes.
inline int SelfIntersections(const Mesh& mesh, int neighbourhood = 2) {
  const int nv = mesh.num_vertices(), nf = mesh.num_triangles();
  if (nf == 0) return 0;
  // vertex adjacency, then each vertex's neighbourhood (BFS to `neighbourhood` edges)
  std::vector<std::vector<int>> adjacent(static_cast<size_t>(nv));
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int i = 0; i < 3; ++i) adjacent[static_cast<size_t>(t[i])].push_back(t[(i + 1) % 3]);
    for (int i = 0; i < 3; ++i) adjacent[static_cast<size_t>(t[(i + 1) % 3])].push_back(t[i]);
  }
  std::vector<std::vector<int>> near(static_cast<size_t>(nv));
  std::vector<int> depth(static_cast<size_t>(nv), -1);
  for (int v = 0; v < nv; ++v) {
    std::vector<int> seen = {v};
    depth[static_cast<size_t>(v)] = 0;
    for (size_t k = 0; k < seen.size(); ++k) {
      const int u = seen[k];
      if (depth[static_cast<size_t>(u)] == neighbourhood) continue;
      for (const int w : adjacent[static_cast<size_t>(u)]) {
        if (depth[static_cast<size_t>(w)] < 0) {
          depth[static_cast<size_t>(w)] = depth[static_cast<size_t>(u)] + 1;
          seen.push_back(w);
        }
      }
    }
    for (const int u : seen) depth[static_cast<size_t>(u)] = -1;
    std::sort(seen.begin(), seen.end());
    near[static_cast<size_t>(v)] = std::move(seen);
  }
  auto neighbours = [&](const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
    for (int i = 0; i < 3; ++i) {
      const std::vector<int>& n = near[static_cast<size_t>(a[i])];
      for (int j = 0; j < 3; ++j) {
        if (std::binary_search(n.begin(), n.end(), b[j])) return true;
      }
    }
    return false;
  };
  // grid of cells about the mean edge length; each triangle goes into every cell its box touches
  double edge = 0.0;
  for (const Eigen::Vector3i& t : mesh.triangles)
    edge += (mesh.positions[t[0]] - mesh.positions[t[1]]).norm();
  const double cell = std::max(2.0 * edge / nf, 1e-9);
  std::unordered_map<int64_t, std::vector<int>> grid;
  auto key = [](int64_t i, int64_t j, int64_t k) {
    return (i * 73856093) ^ (j * 19349663) ^ (k * 83492791);
  };
  std::vector<std::array<Vec3, 3>> corners(static_cast<size_t>(nf));
  std::vector<std::array<int64_t, 6>> boxes(static_cast<size_t>(nf));
  for (int f = 0; f < nf; ++f) {
    const Eigen::Vector3i& t = mesh.triangles[static_cast<size_t>(f)];
    auto& c = corners[static_cast<size_t>(f)];
    for (int i = 0; i < 3; ++i) c[i] = mesh.positions[t[i]];
    auto& box = boxes[static_cast<size_t>(f)];
    for (int a = 0; a < 3; ++a) {
      box[a] = static_cast<int64_t>(std::floor(std::min({c[0](a), c[1](a), c[2](a)}) / cell));
      box[3 + a] = static_cast<int64_t>(std::floor(std::max({c[0](a), c[1](a), c[2](a)}) / cell));
    }
    for (int64_t i = box[0]; i <= box[3]; ++i) {
      for (int64_t j = box[1]; j <= box[4]; ++j) {
        for (int64_t k = box[2]; k <= box[5]; ++k) grid[key(i, j, k)].push_back(f);
      }
    }
  }
  std::set<std::pair<int, int>> crossing;
  for (const auto& [cell_key, faces] : grid) {
    for (size_t x = 0; x < faces.size(); ++x) {
      for (size_t y = x + 1; y < faces.size(); ++y) {
        const int f = std::min(faces[x], faces[y]), g = std::max(faces[x], faces[y]);
        if (f == g || crossing.count({f, g})) continue;
        const auto& bf = boxes[static_cast<size_t>(f)];
        const auto& bg = boxes[static_cast<size_t>(g)];
        if (bf[3] < bg[0] || bg[3] < bf[0] || bf[4] < bg[1] || bg[4] < bf[1] || bf[5] < bg[2] ||
            bg[5] < bf[2])
          continue;
        if (neighbours(mesh.triangles[static_cast<size_t>(f)],
                       mesh.triangles[static_cast<size_t>(g)]))
          continue;
        if (internal::TrianglesCross(corners[static_cast<size_t>(f)],
                                     corners[static_cast<size_t>(g)]))
          crossing.insert({f, g});
      }
    }
  }
  return static_cast<int>(crossing.size());
}

/// Builds `skin` on the skeleton `q` (a bend of radius bend_factor R) and prints how many triangle
/// pairs cross, within 2- and 8-edge neighbourhoods (the known-failure tests report how far from
/// passing they are). @return the 2-edge count.
template <typename SkinType>
int CrossingsOnABend(SkinType* skin, const Points& q, double bend_factor) {
  skin->Bind(static_cast<int>(q.rows()));
  Mesh mesh;
  skin->Build(q, &mesh);
  const int near = SelfIntersections(mesh), far = SelfIntersections(mesh, 8);
  std::printf("bend radius %.1f R: %d crossing pairs (2-edge neighbourhood), %d (8-edge)\n",
              bend_factor, near, far);
  return near;
}

/// Number of vertices whose triangles do not form exactly one closed, consistently oriented
/// fan: the edges opposite the vertex must chain into one cycle.
inline int BadVertexFans(const Mesh& mesh) {
  std::vector<std::map<int, int>> next(
      static_cast<size_t>(mesh.num_vertices()));  // opposite edge a -> b
  std::vector<bool> bad(static_cast<size_t>(mesh.num_vertices()), false);
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int i = 0; i < 3; ++i) {
      auto& fan = next[static_cast<size_t>(t[i])];
      if (!fan.emplace(t[(i + 1) % 3], t[(i + 2) % 3]).second)
        bad[static_cast<size_t>(t[i])] = true;
    }
  }
  int count = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const auto& fan = next[static_cast<size_t>(v)];
    if (fan.empty()) continue;  // an unused vertex is not part of the surface
    bool ok = !bad[static_cast<size_t>(v)];
    // walk the cycle from any start: it must come back after visiting every edge
    int at = fan.begin()->first;
    size_t steps = 0;
    while (ok && steps < fan.size()) {
      const auto it = fan.find(at);
      if (it == fan.end()) {
        ok = false;
        break;
      }
      at = it->second;
      ++steps;
      if (at == fan.begin()->first) break;
    }
    ok = ok && steps == fan.size() && at == fan.begin()->first;
    count += ok ? 0 : 1;
  }
  return count;
}

}  // namespace viscera::skin::testing
