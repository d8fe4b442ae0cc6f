#pragma once
/// MeshRenderer: draws indexed triangle meshes with Blinn-Phong shading and a light at
/// the camera (a laparoscope carries its light), into the current OffscreenContext.
#include <cstdint>
#include <memory>

#include <Eigen/Dense>

#include "render/shader_program.h"

namespace viscera::render {

/// #V by 3 vertex attributes (float, interleaved x y z: uploaded as they are).
using VerticesF = Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// #F by 3 vertex indices per triangle.
using TrianglesU = Eigen::Matrix<uint32_t, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// Surface look. Colours are linear RGB in [0, 1].
struct Material {
  Eigen::Vector3f albedo{0.8f, 0.45f, 0.4f};
  float ambient = 0.15f;   ///< fraction of albedo lit regardless of the light
  float specular = 0.35f;  ///< strength of the white highlight (moist tissue shines)
  float shininess = 40.0f; ///< Blinn-Phong exponent
};

/// Where the camera is and what it sees.
struct CameraMatrices {
  Eigen::Matrix4f view = Eigen::Matrix4f::Identity();        ///< world to view (rigid)
  Eigen::Matrix4f projection = Eigen::Matrix4f::Identity();  ///< view to clip
};

class MeshRenderer {
 public:
  /// Compiles the shaders and creates the GL buffers.
  /// @pre an OffscreenContext of GL >= 3.3 is current on this thread, and stays the
  ///      context this renderer is used and destroyed with.
  /// @throws std::runtime_error when the context is older than GL 3.3.
  MeshRenderer();
  ~MeshRenderer();
  MeshRenderer(const MeshRenderer&) = delete;
  MeshRenderer& operator=(const MeshRenderer&) = delete;

  /// Clears colour (linear RGB in [0, 1]) and depth.
  void Clear(const Eigen::Vector3f& rgb);

  /// Draws one mesh with depth test, both faces lit (the camera may enter the tube).
  /// @param positions #V by 3 vertex positions (m, world frame).
  /// @param normals   #V by 3 unit vertex normals (world frame).
  /// @param triangles #F by 3 indices into positions.
  /// @throws InputError when sizes disagree or an index is out of range.
  /// @throws std::runtime_error when GL reports an error.
  void Draw(const VerticesF& positions, const VerticesF& normals, const TrianglesU& triangles,
            const CameraMatrices& camera, const Material& material);

 private:
  std::unique_ptr<ShaderProgram> program_;
  unsigned vertex_array_ = 0;
  unsigned position_buffer_ = 0;
  unsigned normal_buffer_ = 0;
  unsigned index_buffer_ = 0;
  // Bytes allocated in each buffer: grow only, then update in place.
  long position_capacity_ = 0;
  long normal_capacity_ = 0;
  long index_capacity_ = 0;
  int u_view_ = -1, u_projection_ = -1, u_albedo_ = -1, u_ambient_ = -1, u_specular_ = -1,
      u_shininess_ = -1;
};

}  // namespace viscera::render
