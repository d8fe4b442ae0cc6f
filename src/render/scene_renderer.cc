#include "render/scene_renderer.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"
#include "render/gl.h"
#include "render/target_patch.h"
#include "render/tessellation.h"
#include "spline/catmull_rom.h"

namespace viscera::render {

SceneRenderer::SceneRenderer(const mechanics::ModelParams& params, Palette palette,
                             SceneOptions options)
    : tool_params_(params.tools),
      palette_(std::move(palette)),
      options_(options),
      length_(params.length),
      radius_(params.radius) {
  if (!options_.textures) DropTextures(&palette_);
  if (options_.static_layer) static_layer_ = std::make_unique<StaticLayer>();
  if (options_.static_layer && options_.keep_intestine)
    intestine_layer_ = std::make_unique<StaticLayer>();
  renderer_.set_serosa_per_vertex(options_.serosa_per_vertex);
  renderer_.set_integer_exponents(options_.integer_exponents);
  // every material's program compiled now: a first tool or damaged part holds up no frame
  for (const Material* m : {&palette_.intestine, &palette_.damage, &palette_.tool,
                            &palette_.mesentery, &palette_.target, &palette_.cavity_wall}) {
    renderer_.Prepare(*m);
  }
  const Vec3 around = params.initial_q.rows() > 0
                          ? Vec3(params.initial_q.colwise().mean().transpose())
                          : Vec3(Vec3::Zero());
  int unnamed = 0;
  TriMesh cpu;
  for (const collision::Obstacle& o : params.obstacles) {
    cpu.Clear();
    AppendObstacle(o, around, options_.plane_half_size, &cpu);
    StaticMesh s;
    s.mesh = std::make_unique<GpuMesh>();
    s.mesh->Upload(cpu);
    // the cavity wall is seen from inside (back faces): a scope outside it sees through its
    // near side; closed organs show their front; a plane both ways
    if (o.inside) {
      s.material = palette_.cavity_wall;
      s.faces = Faces::kBack;
    } else if (o.kind == collision::ObstacleKind::kPlane) {
      s.material = palette_.cavity_wall;
      s.faces = Faces::kBoth;
    } else {
      s.material = palette_.Organ(o.name, &unnamed);
      s.faces = Faces::kFront;
    }
    static_triangles_ += cpu.num_triangles();
    obstacles_.push_back(std::move(s));
  }
  // the task's targets: patches that never move, drawn like the organs
  for (const mechanics::TargetParams& t : params.task.targets) {
    cpu.Clear();
    AppendTargetPatch(t, &cpu);
    StaticMesh s;
    s.mesh = std::make_unique<GpuMesh>();
    s.mesh->Upload(cpu);
    s.material = palette_.target;
    s.faces = Faces::kBoth;
    static_triangles_ += cpu.num_triangles();
    obstacles_.push_back(std::move(s));
  }
  // the mesentery film: one rung per tether (at most one per control point)
  num_points_ = static_cast<int>(params.initial_q.rows());
  if (params.mesentery && num_points_ >= 4) {
    const mechanics::MesenteryParams& m = *params.mesentery;
    const int rungs = std::min(m.tethers > 0 ? m.tethers : num_points_, num_points_);
    for (int k = 0; k < rungs; ++k) {
      const double s = static_cast<double>(k) / (rungs - 1);
      membrane_s_.push_back(s);
      membrane_root_.push_back(m.root_start + s * (m.root_end - m.root_start));
    }
    membrane_edge_.resize(membrane_s_.size());
    for (const auto& point : m.lengths) membrane_across_ = std::max(membrane_across_, point.second);
  }
}

SceneRenderer::~SceneRenderer() = default;

bool SceneRenderer::IntestineStill(const skin::Mesh& intestine, const CameraMatrices& camera,
                                   int width, int height) const {
  if (intestine.positions.size() != kept_positions_.size()) return false;
  const Eigen::Matrix4d clip = (camera.projection * camera.view).cast<double>();
  const double half_width = 0.5 * width, half_height = 0.5 * height;
  const double tolerance = options_.keep_tolerance_px;
  for (size_t i = 0; i < kept_positions_.size(); ++i) {
    const Vec3& was = kept_positions_[i];
    const Vec3& is = intestine.positions[i];
    if (was == is) continue;
    const Eigen::Vector4d a = clip * was.homogeneous();
    const Eigen::Vector4d b = clip * is.homogeneous();
    // a moving vertex at or behind the eye's plane: its pixels are not known here
    if (a.w() <= 1e-6 || b.w() <= 1e-6) return false;
    const double dx = (b.x() / b.w() - a.x() / a.w()) * half_width;
    const double dy = (b.y() / b.w() - a.y() / a.w()) * half_height;
    if (std::abs(dx) > tolerance || std::abs(dy) > tolerance) return false;
  }
  return true;
}

void SceneRenderer::DrawStatic(const CameraMatrices& camera) {
  for (const StaticMesh& s : obstacles_) renderer_.Draw(*s.mesh, camera, s.material, s.faces);
}

void SceneRenderer::DrawIntestine(const skin::Mesh& intestine, const CameraMatrices& camera,
                                  int viewport_height) {
  // near to far, roughly: the bowel and the tools before the wall and organs behind them, so the
  // depth test rejects the wall's hidden fragments before they are shaded
  intestine_cpu_.Clear();
  const Faces faces = options_.intestine_back_faces ? Faces::kBoth : Faces::kFront;
  intestine_blocks_.clear();
  if (!damage_.empty() && !intestine.positions.empty() &&
      intestine.surface.size() == intestine.positions.size()) {
    // each triangle in one of the two colours, by where along the bowel its middle lies (the
    // whole skin: a damaged bowel is drawn without culling)
    AppendSkin(intestine, length_, radius_, &intestine_cpu_);
    intestine_counts_ = {};
    intestine_counts_.triangles = intestine_counts_.triangles_drawn = intestine.num_triangles();
    healthy_indices_.clear();
    damaged_indices_.clear();
    for (const Eigen::Vector3i& t : intestine.triangles) {
      const double s = (intestine.surface[t[0]].x() + intestine.surface[t[1]].x() +
                        intestine.surface[t[2]].x()) /
                       3.0;
      bool hurt = false;
      for (const auto& [from, to] : damage_) hurt = hurt || (s >= from && s <= to);
      std::vector<uint32_t>& out = hurt ? damaged_indices_ : healthy_indices_;
      for (int k = 0; k < 3; ++k) out.push_back(static_cast<uint32_t>(t[k]));
    }
    const float* texture =
        intestine_cpu_.texture.empty() ? nullptr : intestine_cpu_.texture[0].data();
    const long n = intestine_cpu_.num_vertices();
    intestine_gpu_.Upload(intestine_cpu_.positions[0].data(), intestine_cpu_.normals[0].data(), n,
                          healthy_indices_.data(), static_cast<long>(healthy_indices_.size()),
                          texture);
    damaged_gpu_.Upload(intestine_cpu_.positions[0].data(), intestine_cpu_.normals[0].data(), n,
                        damaged_indices_.data(), static_cast<long>(damaged_indices_.size()),
                        texture);
    renderer_.Draw(intestine_gpu_, camera, palette_.intestine, faces);
    renderer_.Draw(damaged_gpu_, camera, palette_.damage, faces);
  } else {
    if (options_.cull_intestine && options_.level_of_detail && intestine.tube.rings >= 2) {
      intestine_counts_ = detail_.Append(intestine, length_, radius_, camera, viewport_height,
                                         options_.detail_tolerance_px, &intestine_cpu_);
      intestine_blocks_ = detail_.blocks();
    } else if (options_.cull_intestine) {
      intestine_counts_ = culler_.Append(intestine, length_, radius_, camera, &intestine_cpu_);
    } else {
      AppendSkin(intestine, length_, radius_, &intestine_cpu_);
      intestine_counts_ = {};
      intestine_counts_.triangles = intestine_counts_.triangles_drawn = intestine.num_triangles();
    }
    intestine_gpu_.Upload(intestine_cpu_);
    renderer_.Draw(intestine_gpu_, camera, palette_.intestine, faces);
  }
}

void SceneRenderer::Draw(const skin::Mesh& intestine, std::span<const mechanics::ToolState> tools,
                         const CameraMatrices& camera, const Points* skeleton) {
  ThrowUnless(tools.empty() || tools.size() == tool_params_.size(),
              "SceneRenderer::Draw: ", tools.size(), " tool states for ", tool_params_.size(),
              " tools");
  const bool layered = static_layer_ != nullptr;
  GLint viewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_VIEWPORT, viewport);
  intestine_kept_ = false;
  if (layered) {
    bool static_drawn = false;
    if (!static_layer_->Holds(camera, viewport[2], viewport[3])) {
      static_layer_->BeginDrawing(camera, viewport[2], viewport[3]);
      renderer_.Clear(palette_.background);
      DrawStatic(camera);
      static_layer_->EndDrawing();
      static_drawn = true;
    }
    if (intestine_layer_ != nullptr) {
      // the static scene and the intestine as last drawn, while the bowel rests
      intestine_kept_ =
          !static_drawn && intestine_layer_->Holds(camera, viewport[2], viewport[3]) &&
          damage_ == kept_damage_ && IntestineStill(intestine, camera, viewport[2], viewport[3]);
      if (!intestine_kept_) {
        intestine_layer_->BeginDrawing(camera, viewport[2], viewport[3]);
        static_layer_->CopyToBound();
        DrawIntestine(intestine, camera, viewport[3]);
        intestine_layer_->EndDrawing();
        kept_positions_ = intestine.positions;
        kept_damage_ = damage_;
      }
      intestine_layer_->CopyToBound();
    } else {
      static_layer_->CopyToBound();
      DrawIntestine(intestine, camera, viewport[3]);
    }
  } else {
    renderer_.Clear(palette_.background);
    DrawIntestine(intestine, camera, viewport[3]);
  }

  tools_cpu_.Clear();
  for (size_t i = 0; i < tools.size(); ++i) {
    const mechanics::ToolState& t = tools[i];
    const mechanics::ToolParams& p = tool_params_[i];
    if (!t.initialized) continue;  // never had a target: still outside, at its port
    AppendTool(p.port, t.tip, t.orientation, t.jaw, p.radius, p.length, &tools_cpu_);
  }
  tools_gpu_.Upload(tools_cpu_);
  renderer_.Draw(tools_gpu_, camera, palette_.tool, Faces::kFront);
  if (!layered) DrawStatic(camera);
  // translucent last: it blends over everything opaque behind it
  membrane_cpu_.Clear();
  if (skeleton != nullptr && !membrane_s_.empty() && skeleton->rows() == num_points_) {
    const spline::CatmullRom curve(num_points_);
    for (size_t k = 0; k < membrane_s_.size(); ++k)
      membrane_edge_[k] = curve.Position(*skeleton, membrane_s_[k]);
    AppendRuledFilm(membrane_root_, membrane_edge_, length_, membrane_across_, &membrane_cpu_);
    membrane_gpu_.Upload(membrane_cpu_);
    renderer_.Draw(membrane_gpu_, camera, palette_.mesentery, Faces::kBoth);
  }
  triangles_ = static_triangles_ + intestine_cpu_.num_triangles() + tools_cpu_.num_triangles() +
               membrane_cpu_.num_triangles();
}

}  // namespace viscera::render
