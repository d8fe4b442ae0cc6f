#include "render/scene_renderer.h"

#include "common/check.h"
#include "render/target_patch.h"
#include "render/tessellation.h"

namespace viscera::render {

SceneRenderer::SceneRenderer(const mechanics::ModelParams& params, Palette palette, SceneOptions options)
    : tool_params_(params.tools), palette_(std::move(palette)), options_(options) {
  const Vec3 around = params.initial_q.rows() > 0 ? Vec3(params.initial_q.colwise().mean().transpose())
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
}

SceneRenderer::~SceneRenderer() = default;

void SceneRenderer::Draw(const skin::Mesh& intestine, std::span<const mechanics::ToolState> tools,
                         const CameraMatrices& camera) {
  ThrowUnless(tools.empty() || tools.size() == tool_params_.size(), "SceneRenderer::Draw: ", tools.size(),
              " tool states for ", tool_params_.size(), " tools");
  renderer_.Clear(palette_.background);
  for (const StaticMesh& s : obstacles_) renderer_.Draw(*s.mesh, camera, s.material, s.faces);

  intestine_cpu_.Clear();
  AppendSkin(intestine, &intestine_cpu_);
  intestine_gpu_.Upload(intestine_cpu_);
  renderer_.Draw(intestine_gpu_, camera, palette_.intestine,
                 options_.intestine_back_faces ? Faces::kBoth : Faces::kFront);

  tools_cpu_.Clear();
  for (size_t i = 0; i < tools.size(); ++i) {
    const mechanics::ToolState& t = tools[i];
    const mechanics::ToolParams& p = tool_params_[i];
    if (!t.initialized) continue;  // never had a target: still outside, at its port
    AppendTool(p.port, t.tip, t.orientation, t.jaw, p.radius, p.length, &tools_cpu_);
  }
  tools_gpu_.Upload(tools_cpu_);
  renderer_.Draw(tools_gpu_, camera, palette_.tool, Faces::kFront);
  triangles_ = static_triangles_ + intestine_cpu_.num_triangles() + tools_cpu_.num_triangles();
}

}  // namespace viscera::render
