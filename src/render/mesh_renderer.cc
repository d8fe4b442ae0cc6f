#include "render/mesh_renderer.h"

#include <stdexcept>

#include "common/check.h"
#include "render/gl.h"

namespace viscera::render {
namespace {

constexpr char kVertexShader[] = R"(#version 330 core
uniform mat4 u_view;
uniform mat4 u_projection;
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
out vec3 v_position;  // view space
out vec3 v_normal;    // view space
void main() {
  vec4 p = u_view * vec4(a_position, 1.0);
  v_position = p.xyz;
  v_normal = mat3(u_view) * a_normal;  // u_view is rigid: no inverse transpose needed
  gl_Position = u_projection * p;
}
)";

// Blinn-Phong with the light at the eye: the light and view directions coincide, so
// the half vector is the view direction and both lobes are powers of n.v. A sharp lobe
// (u_shininess) and a broad one (u_sheen) together give the wet look of mucosa. The
// light falls off as 1 / (1 + (d / range)^2) with the distance d from the scope.
constexpr char kFragmentShader[] = R"(#version 330 core
uniform vec3 u_albedo;
uniform float u_ambient;
uniform float u_specular;
uniform float u_shininess;
uniform float u_sheen;
uniform float u_sheen_shininess;
uniform float u_metallic;
uniform float u_light_range;
uniform float u_opacity;
in vec3 v_position;
in vec3 v_normal;
out vec4 frag_colour;
void main() {
  vec3 to_eye = normalize(-v_position);
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  float diffuse = max(dot(n, to_eye), 0.0);
  float light = 1.0;
  if (u_light_range > 0.0) {
    float d = length(v_position) / u_light_range;
    light = 1.0 / (1.0 + d * d);
  }
  float highlight = u_specular * pow(diffuse, u_shininess) + u_sheen * pow(diffuse, u_sheen_shininess);
  vec3 highlight_colour = mix(vec3(1.0), u_albedo, u_metallic);
  vec3 colour = u_albedo * (u_ambient + (1.0 - u_ambient) * diffuse * light) +
                highlight_colour * (highlight * light);
  frag_colour = vec4(min(colour, vec3(1.0)), u_opacity);
}
)";

}  // namespace

MeshRenderer::MeshRenderer() {
  GLint major = 0;
  GLint minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 33) {
    throw std::runtime_error(Cat("MeshRenderer needs GL 3.3, the context offers ", major, ".", minor));
  }
  program_ = std::make_unique<ShaderProgram>(kVertexShader, kFragmentShader);
  u_view_ = program_->Uniform("u_view");
  u_projection_ = program_->Uniform("u_projection");
  u_albedo_ = program_->Uniform("u_albedo");
  u_ambient_ = program_->Uniform("u_ambient");
  u_specular_ = program_->Uniform("u_specular");
  u_shininess_ = program_->Uniform("u_shininess");
  u_sheen_ = program_->Uniform("u_sheen");
  u_sheen_shininess_ = program_->Uniform("u_sheen_shininess");
  u_metallic_ = program_->Uniform("u_metallic");
  u_light_range_ = program_->Uniform("u_light_range");
  u_opacity_ = program_->Uniform("u_opacity");
  stream_ = std::make_unique<GpuMesh>();
}

MeshRenderer::~MeshRenderer() = default;

void MeshRenderer::Clear(const Eigen::Vector3f& rgb) {
  glClearColor(rgb.x(), rgb.y(), rgb.z(), 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

void MeshRenderer::Draw(const VerticesF& positions, const VerticesF& normals,
                        const TrianglesU& triangles, const CameraMatrices& camera,
                        const Material& material) {
  ThrowUnless(normals.rows() == positions.rows(), "MeshRenderer::Draw: ", positions.rows(),
              " positions but ", normals.rows(), " normals");
  if (triangles.rows() == 0) return;
  // Eigen's row-major #V by 3 arrays are the interleaved layout GL takes.
  stream_->Upload(positions.data(), normals.data(), positions.rows(), triangles.data(),
                  static_cast<long>(triangles.size()));
  Draw(*stream_, camera, material);
}

void MeshRenderer::Draw(const GpuMesh& mesh, const CameraMatrices& camera, const Material& material,
                        Faces faces) {
  if (mesh.num_indices() == 0) return;
  // Eigen's default column-major storage is what GL expects: no transpose
  program_->Use();
  glUniformMatrix4fv(u_view_, 1, GL_FALSE, camera.view.data());
  glUniformMatrix4fv(u_projection_, 1, GL_FALSE, camera.projection.data());
  glUniform3fv(u_albedo_, 1, material.albedo.data());
  glUniform1f(u_ambient_, material.ambient);
  glUniform1f(u_specular_, material.specular);
  glUniform1f(u_shininess_, material.shininess);
  glUniform1f(u_sheen_, material.sheen);
  glUniform1f(u_sheen_shininess_, material.sheen_shininess);
  glUniform1f(u_metallic_, material.metallic);
  glUniform1f(u_light_range_, camera.light_range);
  glUniform1f(u_opacity_, material.opacity);
  glEnable(GL_DEPTH_TEST);
  const bool translucent = material.opacity < 1.0f;
  if (translucent) {
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
  }
  if (faces == Faces::kBoth) {
    glDisable(GL_CULL_FACE);
  } else {
    glEnable(GL_CULL_FACE);
    glCullFace(faces == Faces::kFront ? GL_BACK : GL_FRONT);
  }
  mesh.Draw();
  if (translucent) {
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
  }

  const GLenum error = glGetError();
  if (error != GL_NO_ERROR) throw std::runtime_error(Cat("GL error 0x", std::hex, error, " in Draw"));
}

}  // namespace viscera::render
