#pragma once
/// MeshRenderer: draws indexed triangle meshes with Blinn-Phong shading and a light at
/// the camera (a laparoscope carries its light), into the current OffscreenContext.
#include <compare>
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include <Eigen/Dense>

#include "render/gpu_mesh.h"
#include "render/shader_program.h"

namespace viscera::render {

/// #V by 3 vertex attributes (float, interleaved x y z: uploaded as they are).
using VerticesF = Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// #F by 3 vertex indices per triangle.
using TrianglesU = Eigen::Matrix<uint32_t, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// A procedural texture, computed per fragment from the mesh's texture-space points (no
/// image assets; the same points and pattern always give the same pixels).
enum class Pattern {
  kPlain,       ///< the albedo alone
  kPeritoneum,  ///< mottled pale wall with a network of fine vessels
  kSerosa,      ///< the bowel's surface: vessels around the tube (vasa recta), a patchy wet film
  kMesentery,   ///< fat with vessels running from the root to the bowel; vessels more opaque
};

/// Surface look. Colours are linear RGB in [0, 1].
struct Material {
  Eigen::Vector3f albedo{0.8f, 0.45f, 0.4f};
  float ambient = 0.15f;    ///< fraction of albedo lit regardless of the light
  float specular = 0.35f;   ///< strength of the white highlight (moist tissue shines)
  float shininess = 40.0f;  ///< Blinn-Phong exponent
  /// A second, broad highlight lobe (strength, exponent): the wet film on mucosa shines
  /// in a wide soft glow around its sharp highlight. 0: none.
  float sheen = 0.0f;
  float sheen_shininess = 6.0f;
  /// 0: white highlights (dielectric: tissue); 1: highlights tinted by the albedo (metal).
  float metallic = 0.0f;
  /// < 1: a translucent film (the mesentery), blended over what was drawn before it and
  /// not hiding what is drawn after (no depth write): draw it after the opaque meshes.
  float opacity = 1.0f;
  Pattern pattern = Pattern::kPlain;
  Eigen::Vector3f vessel{0.55f, 0.07f, 0.09f};  ///< colour of the pattern's vessels
};

/// Which faces a draw keeps. Closed surfaces seen from outside keep front faces; the
/// inner wall of a cavity (an outward-oriented surface seen from inside) keeps back faces,
/// so a camera outside it sees through its near side.
enum class Faces { kBoth, kFront, kBack };

/// Where the camera is and what it sees.
struct CameraMatrices {
  Eigen::Matrix4f view = Eigen::Matrix4f::Identity();        ///< world to view (rigid)
  Eigen::Matrix4f projection = Eigen::Matrix4f::Identity();  ///< view to clip
  /// The laparoscope's light, at the eye, falls to half its intensity at this distance
  /// (m): near tissue is bright, far tissue dark, as through a real scope. 0: no falloff.
  float light_range = 0.0f;
  /// The light's spot cone around the optical axis (view -z), half angles in degrees: full
  /// strength within `spot_inner_deg`, fading smoothly to none at `spot_outer_deg`. 0: no cone.
  float spot_inner_deg = 0.0f;
  float spot_outer_deg = 0.0f;
};

/// GLSL of `float name(float x)`, x to the power n (n >= 1) as a product of x's repeated squares
/// (at most 2 log2(n) multiplications).
/// @throws InputError for n < 1.
std::string IntegerPowerSource(const std::string& name, int n);

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

  /// Draws one mesh with depth test, both faces lit (the camera may enter the tube); its
  /// texture space is its world positions.
  /// @param positions #V by 3 vertex positions (m, world frame).
  /// @param normals   #V by 3 unit vertex normals (world frame).
  /// @param triangles #F by 3 indices into positions.
  /// @throws InputError when sizes disagree or an index is out of range.
  /// @throws std::runtime_error when GL reports an error.
  void Draw(const VerticesF& positions, const VerticesF& normals, const TrianglesU& triangles,
            const CameraMatrices& camera, const Material& material);

  /// Pattern::kSerosa's three value noises (how far round a vessel reaches, the wet film's
  /// patches, the bands' waviness and the mottle) computed per vertex and interpolated, the bands
  /// themselves (a sine of the position along the bowel) per fragment: no noise is left in the
  /// fragments. Off (the default): all per fragment.
  void set_serosa_per_vertex(bool per_vertex) { serosa_per_vertex_ = per_vertex; }

  /// A material's highlight exponents that are whole numbers from 1 to 256 (every one of the
  /// palette's) raised by products of squares compiled into its program, not by GLSL's pow:
  /// llvmpipe's pow is a log2 and an exp2, each a polynomial, and the bowel's two of them cost
  /// more than a millisecond of a 640x480 frame. The same values up to rounding. On (the
  /// default); off: pow of the uniforms for every material.
  void set_integer_exponents(bool on) { integer_exponents_ = on; }

  /// Compiles the program `material` is drawn with now, rather than at its first Draw (each is
  /// llvmpipe JIT code: a first draw of a material mid-stream would hold up that frame).
  void Prepare(const Material& material) { ProgramFor(material); }

  /// Draws a mesh already in GL buffers (uploaded once for static geometry, or per frame
  /// into a GpuMesh of its own: one buffer set per mesh, so no upload waits for a draw).
  /// @throws std::runtime_error when GL reports an error.
  void Draw(const GpuMesh& mesh, const CameraMatrices& camera, const Material& material,
            Faces faces = Faces::kBoth);

 private:
  // one program per Pattern (kTissueFragmentShader with its PATTERN), serosa per vertex or not,
  // and highlight exponents (0, 0: pow of the uniforms), and its uniforms
  struct ProgramKey {
    Pattern pattern = Pattern::kPlain;
    bool per_vertex = false;
    int shininess = 0, sheen_shininess = 0;
    auto operator<=>(const ProgramKey&) const = default;
  };
  struct Program {
    std::unique_ptr<ShaderProgram> program;
    int u_view = -1, u_projection = -1, u_albedo = -1, u_ambient = -1, u_specular = -1,
        u_shininess = -1, u_sheen = -1, u_sheen_shininess = -1, u_metallic = -1, u_light_range = -1,
        u_opacity = -1, u_vessel = -1, u_spot = -1;
  };
  const Program& ProgramFor(const Material& material);

  std::map<ProgramKey, Program> programs_;  // compiled when first used
  bool serosa_per_vertex_ = false;
  bool integer_exponents_ = true;
  std::unique_ptr<GpuMesh> stream_;  // the mesh of the matrix-based Draw, re-uploaded each call
};

}  // namespace viscera::render
