#pragma once
/// SkinCuller: the part of the intestine's skin a camera may see, nearest first. The skin is cut
/// into chunks of consecutive triangles (the skins emit them ring after ring, so a chunk is a
/// short piece of tube); a chunk whose bounding box lies wholly outside the view volume is left
/// out, and the others are emitted near to far, so that llvmpipe's depth test rejects the hidden
/// fragments of the far ones before they are shaded. Conservative: a triangle with any point in
/// the view volume is always kept.
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "render/gpu_mesh.h"
#include "render/mesh_renderer.h"
#include "skin/mesh.h"

namespace viscera::render {

/// The view volume of `projection * view` as six planes (a x + b y + c z + d >= 0 inside).
class Frustum {
 public:
  explicit Frustum(const Eigen::Matrix4f& view_projection);
  /// True when the box lies wholly outside one of the planes: nothing of it can show.
  bool Outside(const Eigen::AlignedBox3f& box) const;

 private:
  std::array<Eigen::Vector4f, 6> planes_;
};

struct CullCounts {
  int chunks = 0;        ///< of the whole skin
  int chunks_drawn = 0;  ///< in or across the view volume
  long triangles = 0;    ///< of the whole skin
  long triangles_drawn = 0;
};

class SkinCuller {
 public:
  /// @param chunk_triangles triangles per chunk (>= 1).
  explicit SkinCuller(int chunk_triangles = 64);

  /// AppendSkin of the chunks of `mesh` that may show through `camera`, nearest first (by the
  /// depth of their box's centre), with only the vertices they use.
  /// @return what was kept.
  CullCounts Append(const skin::Mesh& mesh, double length, double radius,
                    const CameraMatrices& camera, TriMesh* out);

 private:
  struct Chunk {
    int first = 0;  // triangle
    int count = 0;
    float depth = 0.0f;  // of the box's centre, along the view direction
  };
  int chunk_triangles_;
  std::vector<Chunk> visible_;  // reused
  std::vector<int32_t> remap_;  // skin vertex -> output vertex, -1: not yet emitted
};

}  // namespace viscera::render
