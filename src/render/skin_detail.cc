#include "render/skin_detail.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "common/check.h"

namespace viscera::render {
namespace {

// A level is usable on a ring of `sides` when its step divides the ring and leaves a tube
// (at least 4 sides).
bool Fits(const DetailLevel& level, int sides) {
  return sides % level.side_step == 0 && sides / level.side_step >= 4;
}

// Side `side` of a ring of m, for 0 <= side <= m (side m is side 0).
int Wrap(int side, int m) { return side < m ? side : side - m; }

// A normal that turns by an angle a (rad) across a cell of size L shades like a bump of height
// ~a L / 2: the shading's error counts as that distance.
constexpr double kShadingWeight = 0.5;

}  // namespace

SkinDetail::SkinDetail(int ring_block) : ring_block_(ring_block) {
  VISCERA_DEMAND(ring_block >= 1 && ring_block % kDetailLevels.back().ring_stride == 0);
}

bool SkinDetail::Within(const skin::Mesh& mesh, const Block& block, const DetailLevel& level,
                        double allowed) const {
  const skin::Mesh::TubeGrid& tube = mesh.tube;
  const int m = tube.sides;
  // sides 0 .. m, side m being side 0 again
  auto at = [&](int ring, int side) -> const Vec3& {
    return mesh.positions[static_cast<size_t>(tube.first_vertex + ring * m + Wrap(side, m))];
  };
  auto normal = [&](int ring, int side) -> const Vec3& {
    return mesh.normals[static_cast<size_t>(tube.first_vertex + ring * m + Wrap(side, m))];
  };
  for (int i = block.first_ring; i <= block.last_ring; ++i) {
    const int offset = (i - block.first_ring) % level.ring_stride;
    const int i0 = i - offset;
    const int i1 = std::min(i0 + level.ring_stride, block.last_ring);
    const double t = i1 > i0 ? static_cast<double>(i - i0) / (i1 - i0) : 0.0;
    for (int j = 0; j < m; ++j) {
      const int j0 = j - j % level.side_step;
      const double u = static_cast<double>(j - j0) / level.side_step;
      if (offset == 0 && j == j0) continue;  // a kept vertex
      const int j1 = j0 + level.side_step;
      const Vec3 patch = (1.0 - t) * ((1.0 - u) * at(i0, j0) + u * at(i0, j1)) +
                         t * ((1.0 - u) * at(i1, j0) + u * at(i1, j1));
      const Vec3 shade = (1.0 - t) * ((1.0 - u) * normal(i0, j0) + u * normal(i0, j1)) +
                         t * ((1.0 - u) * normal(i1, j0) + u * normal(i1, j1));
      // the shading's error as a bump of that slope across the coarse cell
      const double cell =
          std::max((at(i1, j0) - at(i0, j0)).norm(), (at(i0, j1) - at(i0, j0)).norm());
      const double turn = (normal(i, j) - shade.normalized()).norm();
      if (std::max((at(i, j) - patch).norm(), kShadingWeight * turn * cell) > allowed) {
        return false;
      }
    }
  }
  return true;
}

int SkinDetail::Strip(const skin::Mesh& mesh, int a, int step_a, int b, int step_b, TriMesh* out) {
  const skin::Mesh::TubeGrid& tube = mesh.tube;
  const int m = tube.sides;
  // each ring's kept vertices in the output, side m (side 0 again) last
  auto ring = [&](int r, int step, std::vector<uint32_t>* at) {
    at->clear();
    for (int side = 0; side <= m; side += step) {
      at->push_back(vertices_(tube.first_vertex + r * m + Wrap(side, m)));
    }
  };
  ring(a, step_a, &ring_a_);
  ring(b, step_b, &ring_b_);
  const int na = m / step_a, nb = m / step_b;
  const size_t first = out->indices.size();
  out->indices.resize(first + 3 * static_cast<size_t>(na + nb));
  uint32_t* to = out->indices.data() + first;
  auto triangle = [&to](uint32_t p, uint32_t q, uint32_t r) {
    to[0] = p;
    to[1] = q;
    to[2] = r;
    to += 3;
  };
  if (step_a == step_b) {
    // the skin's own triangles (tube_rays.h)
    for (int k = 0; k < na; ++k) {
      triangle(ring_a_[k], ring_b_[k + 1], ring_b_[k]);
      triangle(ring_a_[k], ring_a_[k + 1], ring_b_[k + 1]);
    }
    return na + nb;
  }
  // around both rings by angle: the triangle whose new vertex comes first; on a tie the far
  // ring's, which with equal steps gives the skin's own triangles
  int ia = 0, ib = 0;
  while (ia < na || ib < nb) {
    if (ib >= nb || (ia < na && (ia + 1) * step_a < (ib + 1) * step_b)) {
      triangle(ring_a_[ia], ring_a_[ia + 1], ring_b_[ib]);
      ++ia;
    } else {
      triangle(ring_a_[ia], ring_b_[ib + 1], ring_b_[ib]);
      ++ib;
    }
  }
  return na + nb;
}

CullCounts SkinDetail::Append(const skin::Mesh& mesh, double length, double radius,
                              const CameraMatrices& camera, int viewport_height,
                              double tolerance_px, TriMesh* out) {
  const skin::Mesh::TubeGrid& tube = mesh.tube;
  VISCERA_DEMAND(tube.rings >= 2 && tube.sides >= 3 && tolerance_px > 0.0);
  const int m = tube.sides, rings = tube.rings;
  const Frustum frustum(camera.projection * camera.view);
  const Eigen::Vector4f depth_row = -camera.view.row(2).transpose();  // view -z: in front
  auto depth = [&](const Eigen::Vector3f& p) { return depth_row.head<3>().dot(p) + depth_row.w(); };
  // metres at depth 1 per pixel
  const double pixel = 2.0 / (std::max(1, viewport_height) * std::abs(camera.projection(1, 1)));
  const int coarsest = static_cast<int>(kDetailLevels.size()) - 1;

  CullCounts counts;
  counts.triangles = mesh.num_triangles();
  blocks_.clear();
  order_.clear();
  for (int first = 0; first + 1 < rings; first += ring_block_) {
    Block block;
    block.first_ring = first;
    block.last_ring = std::min(first + ring_block_, rings - 1);
    Eigen::AlignedBox3f box;
    for (int v = tube.first_vertex + first * m; v < tube.first_vertex + (block.last_ring + 1) * m;
         ++v) {
      box.extend(mesh.positions[static_cast<size_t>(v)].cast<float>());
    }
    ++counts.chunks;
    block.drawn = !frustum.Outside(box);
    block.level = coarsest;  // outside: its rings take the sides of the drawn neighbour
    if (block.drawn) {
      block.depth = depth(box.center());
      float nearest = std::numeric_limits<float>::infinity();
      for (int corner = 0; corner < 8; ++corner) {
        nearest = std::min(nearest,
                           depth(box.corner(static_cast<Eigen::AlignedBox3f::CornerType>(corner))));
      }
      // the largest error that projects within the tolerance at the block's nearest point
      const double allowed = tolerance_px * pixel * std::max(0.0f, nearest);
      block.level = 0;
      for (int level = coarsest; level > 0; --level) {
        const DetailLevel& l = kDetailLevels[static_cast<size_t>(level)];
        if (Fits(l, m) && Within(mesh, block, l, allowed)) {
          block.level = level;
          break;
        }
      }
      order_.push_back(static_cast<int>(blocks_.size()));
    }
    blocks_.push_back(block);
  }
  // each ring's sides: its block's, the finer of the two on a shared ring, all at the caps
  ring_step_.assign(static_cast<size_t>(rings), kDetailLevels.back().side_step);
  for (const Block& b : blocks_) {
    const int step = kDetailLevels[static_cast<size_t>(b.level)].side_step;
    for (int i = b.first_ring; i <= b.last_ring; ++i) {
      int& s = ring_step_[static_cast<size_t>(i)];
      s = i == b.first_ring || i == b.last_ring ? std::min(s, step) : step;
    }
  }
  ring_step_.front() = ring_step_.back() = 1;
  std::sort(order_.begin(), order_.end(),
            [this](int a, int b) { return blocks_[a].depth < blocks_[b].depth; });

  vertices_.Begin(mesh, length, radius, out);
  // the caps, full detail, when in the view
  const int tube_end = tube.first_triangle + 2 * m * (rings - 1);
  for (const auto& [begin, end] :
       {std::pair{0, tube.first_triangle}, std::pair{tube_end, mesh.num_triangles()}}) {
    if (end <= begin) continue;
    ++counts.chunks;
    Eigen::AlignedBox3f box;
    for (int t = begin; t < end; ++t) {
      for (int k = 0; k < 3; ++k) box.extend(mesh.positions[mesh.triangles[t][k]].cast<float>());
    }
    if (frustum.Outside(box)) continue;
    ++counts.chunks_drawn;
    counts.triangles_drawn += end - begin;
    for (int t = begin; t < end; ++t) {
      for (int k = 0; k < 3; ++k) out->indices.push_back(vertices_(mesh.triangles[t][k]));
    }
  }
  for (int index : order_) {
    Block& b = blocks_[static_cast<size_t>(index)];
    const int stride = kDetailLevels[static_cast<size_t>(b.level)].ring_stride;
    for (int a = b.first_ring; a < b.last_ring; a += stride) {
      const int next = std::min(a + stride, b.last_ring);
      b.triangles += Strip(mesh, a, ring_step_[static_cast<size_t>(a)], next,
                           ring_step_[static_cast<size_t>(next)], out);
    }
    ++counts.chunks_drawn;
    counts.triangles_drawn += b.triangles;
  }
  return counts;
}

}  // namespace viscera::render
