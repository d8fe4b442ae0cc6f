#pragma once
/// SkinDetail: the ring-based skin culled to the view (as SkinCuller) with fewer rings and fewer
/// sides where the tube is far from the camera. The tube (skin::Mesh::tube) is cut into blocks
/// of a few consecutive rings; each block in the view is drawn at the coarsest level whose
/// surface, and shading, stay within `tolerance_px` pixels of the full one at the block's nearest
/// depth, so a loop close to the scope keeps every side and, where it bends, every ring. The
/// coarse levels keep a subset of the skin's own vertices (every 2nd or 4th ring, every 2nd side)
/// with their normals and surface coordinates. A ring shared by two blocks keeps the sides of the
/// finer one, and each pair of consecutive kept rings is joined by a strip that walks both rings by
/// angle, so strips of different sides share every vertex of their common ring: no cracks. The end
/// caps are drawn at full detail.
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "render/gpu_mesh.h"
#include "render/mesh_renderer.h"
#include "render/skin_culling.h"
#include "skin/mesh.h"

namespace viscera::render {

/// A level of detail: every `ring_stride`-th ring and every `side_step`-th side.
struct DetailLevel {
  int ring_stride = 1;
  int side_step = 1;
};

/// Level 0 is the full skin; the others coarser and coarser.
inline constexpr std::array<DetailLevel, 5> kDetailLevels = {
    {{1, 1}, {2, 1}, {4, 1}, {2, 2}, {4, 2}}};

class SkinDetail {
 public:
  /// @param ring_block rings per block (a multiple of the largest ring stride, 4).
  explicit SkinDetail(int ring_block = 4);

  /// One block of the last Append: rings [first_ring, last_ring] of the tube.
  struct Block {
    int first_ring = 0, last_ring = 0;
    int level = 0;       ///< index in kDetailLevels (drawn blocks only)
    bool drawn = false;  ///< in or across the view volume
    int triangles = 0;   ///< drawn
    float depth = 0.0f;  ///< of the box's centre, along the view direction
  };

  /// Appends what of `mesh` may show through `camera` to *out, nearest first, each block at its
  /// level. `viewport_height` (pixels) turns the projection into pixels.
  /// @pre mesh.tube.rings >= 2 (a ring-based skin), tolerance_px > 0.
  /// @return what was kept (chunks: the blocks and the two caps).
  CullCounts Append(const skin::Mesh& mesh, double length, double radius,
                    const CameraMatrices& camera, int viewport_height, double tolerance_px,
                    TriMesh* out);

  const std::vector<Block>& blocks() const { return blocks_; }

 private:
  // True when every left-out vertex of the block lies within `allowed` (m) of the bilinear
  // patch of its coarse cell's corners, and its normal's turn from the patch's (rad) times
  // half the cell's size is within `allowed` too.
  bool Within(const skin::Mesh& mesh, const Block& block, const DetailLevel& level,
              double allowed) const;
  // Triangles between the kept rings a < b with side steps step_a, step_b, walked by angle.
  int Strip(const skin::Mesh& mesh, int a, int step_a, int b, int step_b, TriMesh* out);

  int ring_block_;
  std::vector<Block> blocks_;
  std::vector<int> order_;  // drawn blocks, nearest first
  std::vector<int> ring_step_;
  SkinVertices vertices_;
  std::vector<uint32_t> ring_a_, ring_b_;  // Strip's rings in the output
};

}  // namespace viscera::render
