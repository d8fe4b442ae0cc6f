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

/// Copies the skin's vertices that a drawing uses into a TriMesh, each once, with AppendSkin's
/// texture space (the tube unrolled, or the world positions for a skin without surface
/// coordinates).
class SkinVertices {
 public:
  /// Starts copying vertices of `mesh` to the end of *out (both outlive the copying).
  void Begin(const skin::Mesh& mesh, double length, double radius, TriMesh* out);
  /// The index in *out of skin vertex v, copied on its first use.
  uint32_t operator()(int v) {
    int32_t& at = remap_[static_cast<size_t>(v)];
    if (at < 0) at = Copy(v);
    return static_cast<uint32_t>(base_ + at);
  }

 private:
  int32_t Copy(int v);
  const skin::Mesh* mesh_ = nullptr;
  TriMesh* out_ = nullptr;
  double length_ = 0.0, radius_ = 0.0;
  bool on_tissue_ = false;
  int32_t base_ = 0;
  std::vector<int32_t> remap_;  // skin vertex -> output vertex, -1: not yet copied
  // r cos and r sin of the surface angles met so far (r: the radius they were computed with)
  struct Angle {
    bool set = false;
    uint64_t bits = 0;  // the angle's
    double cos = 0.0, sin = 0.0;
  };
  std::array<Angle, 128> angles_{};
  double angles_radius_ = 0.0;
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
  SkinVertices vertices_;
};

}  // namespace viscera::render
