#pragma once
/// GpuMesh: one indexed triangle mesh in GL buffers (a vertex array object with position,
/// normal, texture-space and index buffers), and TriMesh, its CPU-side twin in the exact layout the
/// buffers take, so an upload is one copy per buffer and no conversion.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace viscera::render {

static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float), "Vector3f must be packed");

/// Triangle mesh on the CPU, float, world frame. Buffers are vectors: Clear() keeps their
/// capacity, so rebuilding a mesh of the same size every frame allocates nothing.
struct TriMesh {
  std::vector<Eigen::Vector3f> positions;  ///< #V, metres
  std::vector<Eigen::Vector3f> normals;    ///< #V, unit, outward
  std::vector<uint32_t> indices;           ///< 3 per triangle, counter-clockwise from outside
  /// #V points of the tissue's own space (m) where the procedural textures are evaluated, so a
  /// pattern stays on the tissue when it moves (the bowel: along it and around it); empty: the
  /// world positions (static geometry).
  std::vector<Eigen::Vector3f> texture;

  int num_vertices() const { return static_cast<int>(positions.size()); }
  int num_triangles() const { return static_cast<int>(indices.size() / 3); }
  void Clear() {
    positions.clear();
    normals.clear();
    indices.clear();
    texture.clear();
  }
};

/// GL buffers of one mesh. Buffers only grow: uploading a mesh no larger than the largest
/// one so far updates them in place.
/// @pre a GL >= 3.3 context is current on this thread for the object's whole life.
class GpuMesh {
 public:
  GpuMesh();
  ~GpuMesh();
  GpuMesh(const GpuMesh&) = delete;
  GpuMesh& operator=(const GpuMesh&) = delete;

  /// Uploads #num_vertices x 3 floats of positions, of normals and of texture-space points
  /// (null: the positions), and num_indices vertex indices (a multiple of 3).
  /// @throws InputError when num_indices is not a multiple of 3 or an index is out of range.
  void Upload(const float* positions, const float* normals, long num_vertices,
              const uint32_t* indices, long num_indices, const float* texture = nullptr);
  /// @throws InputError also when mesh.texture is neither empty nor #V.
  void Upload(const TriMesh& mesh);

  /// Issues the draw call with whatever program and state are current. Nothing when empty.
  void Draw() const;

  long num_indices() const { return num_indices_; }

 private:
  unsigned vertex_array_ = 0;
  unsigned position_buffer_ = 0;
  unsigned normal_buffer_ = 0;
  unsigned texture_buffer_ = 0;
  unsigned index_buffer_ = 0;
  long position_capacity_ = 0;  // bytes
  long normal_capacity_ = 0;
  long texture_capacity_ = 0;
  long index_capacity_ = 0;
  long num_indices_ = 0;
};

}  // namespace viscera::render
