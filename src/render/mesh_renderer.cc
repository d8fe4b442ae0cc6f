#include "render/mesh_renderer.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "common/check.h"
#include "render/gl.h"
#include "render/tissue_shader.h"

namespace viscera::render {

MeshRenderer::MeshRenderer() {
  GLint major = 0;
  GLint minor = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  if (major * 10 + minor < 33) {
    throw std::runtime_error(Cat("MeshRenderer needs GL 3.3, the context offers ", major, ".", minor));
  }
  program_ = std::make_unique<ShaderProgram>(kTissueVertexShader, kTissueFragmentShader);
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
  u_pattern_ = program_->Uniform("u_pattern");
  u_vessel_ = program_->Uniform("u_vessel");
  u_spot_ = program_->Uniform("u_spot");
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
  glUniform1i(u_pattern_, static_cast<int>(material.pattern));
  glUniform3fv(u_vessel_, 1, material.vessel.data());
  const float to_radians = std::numbers::pi_v<float> / 180.0f;
  const bool cone = camera.spot_outer_deg > 0.0f && camera.spot_outer_deg > camera.spot_inner_deg;
  glUniform2f(u_spot_, cone ? std::cos(camera.spot_inner_deg * to_radians) : 0.0f,
              cone ? std::cos(camera.spot_outer_deg * to_radians) : 1.0f);
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
