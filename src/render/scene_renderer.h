#pragma once
/// SceneRenderer: draws one frame of a simulation — the abdominal cavity's wall and organs
/// (the scene's obstacles), the intestine's skin and the tools — into the current
/// OffscreenContext.
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "mechanics/model_params.h"
#include "mechanics/tool.h"
#include "render/gpu_mesh.h"
#include "render/mesh_renderer.h"
#include "render/palette.h"
#include "render/skin_culling.h"
#include "render/skin_detail.h"
#include "render/static_layer.h"
#include "skin/mesh.h"

namespace viscera::render {

struct SceneOptions {
  /// Planes are drawn as squares this size (m) each way around the projection of the
  /// centre of the skeleton's starting pose.
  double plane_half_size = 1.0;
  /// Draw the intestine's back faces too (a scope inside the tube then sees its inner
  /// wall). Off by default: culling them halves the triangles llvmpipe rasterizes (30-40 %
  /// of the render time on the cavity scene) and a scope does not enter tissue.
  bool intestine_back_faces = false;
  /// Procedural textures (Material::pattern). Off: every material plain (DropTextures).
  bool textures = true;
  /// Draw only the pieces of the intestine in or across the view volume, nearest first
  /// (SkinCuller). Off: the whole skin in the skin's order (the reference the tests compare to).
  bool cull_intestine = true;
  /// With cull_intestine, draw the far parts of a ring-based skin with fewer rings and sides
  /// (SkinDetail): their surface stays within `detail_tolerance_px` pixels of the full skin's.
  /// Off: every ring and side (the reference).
  bool level_of_detail = true;
  double detail_tolerance_px = 1.0;
  /// Keep the picture of the static scene (StaticLayer) while the camera stays, and draw only
  /// what moves over a copy of it. Off: everything drawn every frame (the reference).
  bool static_layer = true;
  /// With static_layer, keep the picture of the static scene and the intestine too while the
  /// camera stays and every vertex of the skin stays within `keep_tolerance_px` pixels of where
  /// it was when that picture was drawn (a bowel at rest, a tool moving): a frame then draws
  /// only the tools and the mesentery over a copy of it. Off: the intestine drawn every frame
  /// (the reference).
  bool keep_intestine = true;
  double keep_tolerance_px = 0.25;
  /// The serosa's noises per vertex (MeshRenderer::set_serosa_per_vertex). Off: all of its
  /// pattern per fragment (the reference).
  bool serosa_per_vertex = true;
  /// Whole highlight exponents as products (MeshRenderer::set_integer_exponents). Off: GLSL's
  /// pow (the reference).
  bool integer_exponents = true;
};

class SceneRenderer {
 public:
  /// Tessellates the obstacles of `params` once and uploads them (they never move).
  /// @pre an OffscreenContext (GL >= 3.3) is current on this thread and stays current
  ///      for this object's life; `params` is valid (a Model was built from it).
  SceneRenderer(const mechanics::ModelParams& params, Palette palette = DefaultPalette(),
                SceneOptions options = {});
  ~SceneRenderer();
  SceneRenderer(const SceneRenderer&) = delete;
  SceneRenderer& operator=(const SceneRenderer&) = delete;

  /// Clears to the background and draws the obstacles, the intestine, the tools and, last, the
  /// mesentery (a translucent film from its root to the centre line, when the scene has one and
  /// `skeleton` is given).
  /// @param intestine the skin of the snapshot shown (world frame, outward triangles).
  /// @param tools     one per `params.tools`, in scene order (State::tools); may be empty.
  /// @param skeleton  the snapshot's control points (#N by 3), or null: no mesentery drawn.
  /// @throws InputError when tools has another size than the scene's tools.
  void Draw(const skin::Mesh& intestine, std::span<const mechanics::ToolState> tools,
            const CameraMatrices& camera, const Points* skeleton = nullptr);

  /// Parts of the bowel drawn in the damage colour from the next Draw on: ranges [from, to] of
  /// the curve parameter s (0..1). Needs a skin with surface coordinates (the ring-based ones).
  void SetDamage(std::vector<std::pair<double, double>> ranges) { damage_ = std::move(ranges); }

  const Palette& palette() const { return palette_; }
  /// Triangles drawn in the last frame (obstacles, intestine, tools).
  long triangles() const { return triangles_; }
  /// The intestine's chunks and triangles in the last frame, and how many were drawn.
  const CullCounts& intestine_counts() const { return intestine_counts_; }
  /// Whether the last frame started from the kept picture of the intestine
  /// (SceneOptions::keep_intestine) instead of drawing it.
  bool intestine_kept() const { return intestine_kept_; }
  /// The skin's blocks and their levels of detail in the last frame (empty when it was drawn
  /// without SceneOptions::level_of_detail).
  const std::vector<SkinDetail::Block>& intestine_blocks() const { return intestine_blocks_; }

 private:
  struct StaticMesh {
    std::unique_ptr<GpuMesh> mesh;
    Material material;
    Faces faces = Faces::kBoth;
  };

  void DrawStatic(const CameraMatrices& camera);  // the obstacles and targets
  // the intestine (culled, at its levels of detail, or in two colours when damaged)
  void DrawIntestine(const skin::Mesh& intestine, const CameraMatrices& camera,
                     int viewport_height);
  // every vertex of `intestine` within keep_tolerance_px of the kept picture's
  bool IntestineStill(const skin::Mesh& intestine, const CameraMatrices& camera, int width,
                      int height) const;

  std::vector<mechanics::ToolParams> tool_params_;
  Palette palette_;
  SceneOptions options_;
  MeshRenderer renderer_;
  std::vector<StaticMesh> obstacles_;
  std::unique_ptr<StaticLayer> static_layer_;  // null when SceneOptions::static_layer is off
  // the static scene and the intestine (null without SceneOptions::keep_intestine): the skin's
  // vertices and the damage it was drawn with
  std::unique_ptr<StaticLayer> intestine_layer_;
  std::vector<Vec3> kept_positions_;
  std::vector<std::pair<double, double>> kept_damage_;
  bool intestine_kept_ = false;
  SkinCuller culler_;
  SkinDetail detail_;
  CullCounts intestine_counts_;
  std::vector<SkinDetail::Block> intestine_blocks_;
  TriMesh intestine_cpu_;  // reused: its float copy of the skin
  TriMesh tools_cpu_;
  GpuMesh intestine_gpu_;  // one buffer set per dynamic mesh: no upload waits for a draw
  // the damaged parts of the bowel: the skin's triangles whose middle lies in a range of s
  std::vector<std::pair<double, double>> damage_;
  std::vector<uint32_t> healthy_indices_, damaged_indices_;
  GpuMesh damaged_gpu_;
  GpuMesh tools_gpu_;
  // the mesentery: its root points and curve parameters (empty without [mesentery])
  std::vector<Vec3> membrane_root_, membrane_edge_;
  std::vector<double> membrane_s_;
  double membrane_across_ = 0.0;        // texture space: m from the root to the bowel
  double length_ = 0.0, radius_ = 0.0;  // the tube's: the serosa's texture space
  int num_points_ = 0;
  TriMesh membrane_cpu_;
  GpuMesh membrane_gpu_;
  long static_triangles_ = 0;
  long triangles_ = 0;
};

}  // namespace viscera::render
