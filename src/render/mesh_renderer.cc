#include "render/mesh_renderer.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

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
    throw std::runtime_error(
        Cat("MeshRenderer needs GL 3.3, the context offers ", major, ".", minor));
  }
  ProgramFor(Material{});  // shader errors show at construction
  stream_ = std::make_unique<GpuMesh>();
}

MeshRenderer::~MeshRenderer() = default;

namespace {

// A whole exponent from 1 to 256, else 0.
int WholeExponent(float e) {
  return e >= 1.0f && e <= 256.0f && e == std::floor(e) ? static_cast<int>(e) : 0;
}

}  // namespace

std::string IntegerPowerSource(const std::string& name, int n) {
  ThrowUnless(n >= 1, "IntegerPowerSource: exponent ", n, " is not >= 1");
  // x^n = the product of x^(2^i) over n's bits: at most 2 log2(n) multiplications
  std::string body = "float " + name + "(float x) {\n  float r = 1.0;\n";
  for (int bits = n; bits > 0; bits >>= 1) {
    if ((bits & 1) != 0) body += "  r *= x;\n";
    if (bits > 1) body += "  x *= x;\n";
  }
  return body + "  return r;\n}\n";
}

// Compiles the program of one pattern and exponents the first time a material asks for it: a
// scene compiles only what it draws (every program is JIT code llvmpipe keeps with the context).
const MeshRenderer::Program& MeshRenderer::ProgramFor(const Material& material) {
  ProgramKey key;
  key.pattern = material.pattern;
  key.per_vertex = material.pattern == Pattern::kSerosa && serosa_per_vertex_;
  if (integer_exponents_ && WholeExponent(material.shininess) > 0 &&
      WholeExponent(material.sheen_shininess) > 0) {
    key.shininess = WholeExponent(material.shininess);
    key.sheen_shininess = WholeExponent(material.sheen_shininess);
  }
  Program& p = programs_[key];
  if (p.program != nullptr) return p;
  const std::string version = "#version 330 core\n";
  const std::string vertex_body = std::string(kTissueVertexShader).substr(version.size());
  const char* define = key.per_vertex ? "#define SEROSA_PER_VERTEX 1\n" : "";
  const std::string exponents =
      key.shininess > 0
          ? Cat("#define INTEGER_EXPONENTS 1\n", IntegerPowerSource("PowShininess", key.shininess),
                IntegerPowerSource("PowSheenShininess", key.sheen_shininess))
          : std::string();
  p.program = std::make_unique<ShaderProgram>(
      Cat(version, define, key.per_vertex ? kTissueNoise : "", vertex_body),
      Cat(version, "#define PATTERN ", static_cast<int>(key.pattern), "\n", define, kTissueNoise,
          exponents, kTissueFragmentShader));
  // -1 for a uniform the variant does not use (u_vessel when plain): glUniform ignores it
  auto at = [&](const char* name) { return glGetUniformLocation(p.program->id(), name); };
  p.u_view = at("u_view");
  p.u_projection = at("u_projection");
  p.u_albedo = at("u_albedo");
  p.u_ambient = at("u_ambient");
  p.u_specular = at("u_specular");
  p.u_shininess = at("u_shininess");
  p.u_sheen = at("u_sheen");
  p.u_sheen_shininess = at("u_sheen_shininess");
  p.u_metallic = at("u_metallic");
  p.u_light_range = at("u_light_range");
  p.u_opacity = at("u_opacity");
  p.u_vessel = at("u_vessel");
  p.u_spot = at("u_spot");
  return p;
}

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
  const Program& p = ProgramFor(material);
  p.program->Use();
  glUniformMatrix4fv(p.u_view, 1, GL_FALSE, camera.view.data());
  glUniformMatrix4fv(p.u_projection, 1, GL_FALSE, camera.projection.data());
  glUniform3fv(p.u_albedo, 1, material.albedo.data());
  glUniform1f(p.u_ambient, material.ambient);
  glUniform1f(p.u_specular, material.specular);
  glUniform1f(p.u_shininess, material.shininess);
  glUniform1f(p.u_sheen, material.sheen);
  glUniform1f(p.u_sheen_shininess, material.sheen_shininess);
  glUniform1f(p.u_metallic, material.metallic);
  glUniform1f(p.u_light_range, camera.light_range);
  glUniform1f(p.u_opacity, material.opacity);
  glUniform3fv(p.u_vessel, 1, material.vessel.data());
  const float to_radians = std::numbers::pi_v<float> / 180.0f;
  const bool cone = camera.spot_outer_deg > 0.0f && camera.spot_outer_deg > camera.spot_inner_deg;
  glUniform2f(p.u_spot, cone ? std::cos(camera.spot_inner_deg * to_radians) : 0.0f,
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
  if (error != GL_NO_ERROR)
    throw std::runtime_error(Cat("GL error 0x", std::hex, error, " in Draw"));
}

}  // namespace viscera::render
