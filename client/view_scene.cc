#include "client/view_scene.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/check.h"
#include "render/palette.h"
#include "render/port_scope.h"
#include "render/target_patch.h"
#include "render/tessellation.h"
#include "render/tissue_shader.h"
#include "scene/scene.h"
#include "skin/skin.h"

namespace viscera::client {
namespace {

// Appends numbers with 6 significant digits: 1 um at the scale of an abdomen, a third the
// size of full precision.
void Number(std::string* out, double value) {
  char text[32];
  const int n = std::snprintf(text, sizeof(text), "%.6g", std::isfinite(value) ? value : 0.0);
  out->append(text, static_cast<size_t>(n));
}

template <typename Range>
void Numbers(std::string* out, const Range& values) {
  out->push_back('[');
  bool first = true;
  for (const auto& v : values) {
    if (!first) out->push_back(',');
    first = false;
    Number(out, static_cast<double>(v));
  }
  out->push_back(']');
}

void Vectors(std::string* out, const std::vector<Eigen::Vector3f>& values) {
  out->push_back('[');
  for (size_t i = 0; i < values.size(); ++i) {
    if (i > 0) out->push_back(',');
    for (int a = 0; a < 3; ++a) {
      if (a > 0) out->push_back(',');
      Number(out, values[i][a]);
    }
  }
  out->push_back(']');
}

void Mesh(std::string* out, const render::TriMesh& mesh) {
  out->append("{\"positions\":");
  Vectors(out, mesh.positions);
  out->append(",\"normals\":");
  Vectors(out, mesh.normals);
  if (!mesh.texture.empty()) {
    out->append(",\"texture\":");
    Vectors(out, mesh.texture);
  }
  out->append(",\"indices\":");
  Numbers(out, mesh.indices);
  out->push_back('}');
}

void MaterialJson(std::string* out, const render::Material& m) {
  out->append("{\"albedo\":");
  Numbers(out, std::vector<float>(m.albedo.data(), m.albedo.data() + 3));
  out->append(Cat(",\"ambient\":", m.ambient, ",\"specular\":", m.specular, ",\"shininess\":",
                  m.shininess, ",\"sheen\":", m.sheen, ",\"sheen_shininess\":", m.sheen_shininess,
                  ",\"metallic\":", m.metallic, ",\"opacity\":", m.opacity,
                  ",\"pattern\":", static_cast<int>(m.pattern), ",\"vessel\":"));
  Numbers(out, std::vector<float>(m.vessel.data(), m.vessel.data() + 3));
  out->push_back('}');
}

const char* FacesName(render::Faces faces) {
  switch (faces) {
    case render::Faces::kFront: return "front";
    case render::Faces::kBack: return "back";
    case render::Faces::kBoth: break;
  }
  return "both";
}

Points ControlPoints(const viscera_proto::skeleton_state_t& state) {
  Points q(state.num_points, 3);
  for (int i = 0; i < state.num_points; ++i) {
    for (int a = 0; a < 3; ++a)
      q(i, a) = state.points[static_cast<size_t>(i)][static_cast<size_t>(a)];
  }
  return q;
}

// The camera as the page takes it: view and projection (column-major) and the light.
std::string CameraOf(const render::Laparoscope& scope, int width, int height) {
  const render::CameraMatrices camera = scope.Matrices(width, height);
  std::string out = "{\"view\":";
  Numbers(&out, std::vector<float>(camera.view.data(), camera.view.data() + 16));
  out.append(",\"projection\":");
  Numbers(&out, std::vector<float>(camera.projection.data(), camera.projection.data() + 16));
  out.append(Cat(",\"light_range\":", camera.light_range, ",\"spot_inner_deg\":",
                 camera.spot_inner_deg, ",\"spot_outer_deg\":", camera.spot_outer_deg, "}"));
  return out;
}

// Thrown out of the scene's vet hook, which runs after reading and before settling.
struct GeometryRead {};

}  // namespace

mechanics::ModelParams LoadSceneGeometry(const std::string& path) {
  std::ifstream in(path);
  ThrowUnless(in.good(), "cannot read the scene file ", path);
  std::ostringstream text;
  text << in.rdbuf();
  scene::SceneLimits limits;
  mechanics::ModelParams read;
  limits.vet = [&](const mechanics::ModelParams& params, bool settled) {
    read = params;
    if (!settled) throw GeometryRead{};
  };
  try {
    scene::Scene s = scene::ParseScene(text.str(), path, limits);
    return s.model;  // a scene that does not settle
  } catch (const GeometryRead&) {
    return read;
  }
}

std::string SceneJson(const mechanics::ModelParams& params,
                      const viscera_proto::skeleton_state_t& first, int width, int height) {
  ThrowUnless(first.num_points == params.initial_q.rows(), "the session's skeleton has ",
              first.num_points, " control points, the scene file ", params.initial_q.rows(),
              ": not the session's scene");
  ThrowUnless(width > 0 && height > 0, "frame size ", width, "x", height);
  const render::Palette palette = render::DefaultPalette();
  const render::Laparoscope scope =
      render::SceneLaparoscope(params, ControlPoints(first), width, height);
  // the server's own shaders, in pieces the page puts together as render::MeshRenderer does,
  // after its GLSL ES version and precision
  std::string vertex = render::kTissueVertexShader;
  vertex.erase(0, vertex.find('\n') + 1);  // "#version 330 core"
  std::string out =
      Cat("{\"width\":", width, ",\"height\":", height,
          ",\"shaders\":{\"vertex\":", nlohmann::json(vertex).dump(),
          ",\"noise\":", nlohmann::json(render::kTissueNoise).dump(),
          ",\"fragment\":", nlohmann::json(render::kTissueFragmentShader).dump(), "},\"camera\":");
  out.append(CameraOf(scope, width, height));
  out.append(",\"background\":");
  Numbers(&out, std::vector<float>(palette.background.data(), palette.background.data() + 3));
  const skin::ParametricOptions tube;
  out.append(Cat(",\"tube\":{\"length\":", params.length, ",\"radius\":", params.radius,
                 ",\"radius_min\":", tube.radius_min_factor * params.radius,
                 ",\"radius_max\":", tube.radius_max_factor * params.radius,
                 ",\"rings_per_segment\":", tube.rings_per_segment, ",\"sides\":", tube.sides,
                 ",\"cap_rings\":", tube.cap_rings, ",\"points\":", first.num_points,
                 "},\"materials\":{"));
  out.append("\"intestine\":");
  MaterialJson(&out, palette.intestine);
  out.append(",\"tool\":");
  MaterialJson(&out, palette.tool);
  out.append(",\"mesentery\":");
  MaterialJson(&out, palette.mesentery);
  out.append("},\"meshes\":[");

  // as render::SceneRenderer: obstacles, then the targets
  const Vec3 around = params.initial_q.colwise().mean().transpose();
  int unnamed = 0;
  bool first_mesh = true;
  render::TriMesh cpu;
  const auto add = [&](const render::Material& material, render::Faces faces) {
    if (!first_mesh) out.push_back(',');
    first_mesh = false;
    out.append("{\"material\":");
    MaterialJson(&out, material);
    out.append(Cat(",\"faces\":\"", FacesName(faces), "\",\"mesh\":"));
    Mesh(&out, cpu);
    out.push_back('}');
  };
  for (const collision::Obstacle& o : params.obstacles) {
    cpu.Clear();
    render::AppendObstacle(o, around, 1.0, &cpu);
    if (o.inside) {
      add(palette.cavity_wall, render::Faces::kBack);
    } else if (o.kind == collision::ObstacleKind::kPlane) {
      add(palette.cavity_wall, render::Faces::kBoth);
    } else {
      add(palette.Organ(o.name, &unnamed), render::Faces::kFront);
    }
  }
  for (const mechanics::TargetParams& t : params.task.targets) {
    cpu.Clear();
    render::AppendTargetPatch(t, &cpu);
    add(palette.target, render::Faces::kBoth);
  }
  out.append("],\"tools\":");
  out.append(Cat(params.tools.size()));
  // the mesentery: its root points, the curve parameters of its rungs, how far across it reaches
  out.append(",\"mesentery\":");
  const int n = static_cast<int>(params.initial_q.rows());
  if (params.mesentery && n >= 4) {
    const mechanics::MesenteryParams& m = *params.mesentery;
    const int rungs = std::min(m.tethers > 0 ? m.tethers : n, n);
    std::vector<double> s, root;
    for (int k = 0; k < rungs; ++k) {
      s.push_back(static_cast<double>(k) / (rungs - 1));
      const Vec3 p = m.root_start + s.back() * (m.root_end - m.root_start);
      root.insert(root.end(), {p.x(), p.y(), p.z()});
    }
    double across = 0.0;
    for (const auto& point : m.lengths) across = std::max(across, point.second);
    out.append("{\"s\":");
    Numbers(&out, s);
    out.append(",\"root\":");
    Numbers(&out, root);
    out.append(Cat(",\"across\":", across, "}"));
  } else {
    out.append("null");
  }
  out.append("}\n");
  return out;
}

std::string LookAtCameraJson(const viscera_proto::session_request_t& request, int width,
                             int height) {
  const Vec3 eye(request.camera_eye[0], request.camera_eye[1], request.camera_eye[2]);
  const Vec3 target(request.camera_target[0], request.camera_target[1], request.camera_target[2]);
  const Vec3 up(request.camera_up[0], request.camera_up[1], request.camera_up[2]);
  // as the server's render thread draws a client's camera (server/session_view.h)
  return CameraOf(render::LookAtLaparoscope(eye, target, up, request.camera_fov_deg), width,
                  height);
}

std::string SkeletonJson(const viscera_proto::skeleton_state_t& state,
                         const mechanics::ModelParams& params, const std::vector<ViewedTool>& tools,
                         const std::string& camera) {
  std::string out = Cat("{\"step\":", state.step, ",\"t\":");
  Number(&out, state.sim_time);
  out.append(Cat(",\"utime\":", state.header.utime, ",\"points\":["));
  for (int i = 0; i < state.num_points; ++i) {
    for (int a = 0; a < 3; ++a) {
      if (i > 0 || a > 0) out.push_back(',');
      Number(&out, state.points[static_cast<size_t>(i)][static_cast<size_t>(a)]);
    }
  }
  out.append("],\"tools\":");
  render::TriMesh mesh;
  for (size_t i = 0; i < tools.size() && i < params.tools.size(); ++i) {
    const ViewedTool& t = tools[i];
    if (!t.seen) continue;
    const mechanics::ToolParams& p = params.tools[i];
    const Eigen::Quaterniond q =
        Eigen::Quaterniond(t.orientation[0], t.orientation[1], t.orientation[2], t.orientation[3])
            .normalized();
    render::AppendTool(p.port, Vec3(t.tip[0], t.tip[1], t.tip[2]), q, t.jaw, p.radius, p.length,
                       &mesh);
  }
  Mesh(&out, mesh);
  if (!camera.empty()) out.append(Cat(",\"camera\":", camera));
  out.append("}");
  return out;
}

}  // namespace viscera::client
