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
// the half vector is the view direction.
constexpr char kFragmentShader[] = R"(#version 330 core
uniform vec3 u_albedo;
uniform float u_ambient;
uniform float u_specular;
uniform float u_shininess;
in vec3 v_position;
in vec3 v_normal;
out vec4 frag_colour;
void main() {
  vec3 to_eye = normalize(-v_position);
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  float diffuse = max(dot(n, to_eye), 0.0);
  float highlight = u_specular * pow(diffuse, u_shininess);
  vec3 colour = u_albedo * (u_ambient + (1.0 - u_ambient) * diffuse) + vec3(highlight);
  frag_colour = vec4(min(colour, vec3(1.0)), 1.0);
}
)";

// Uploads `bytes` into `buffer`, reallocating only when it grows.
void Upload(GLenum target, unsigned buffer, const void* data, long bytes, long* capacity) {
  glBindBuffer(target, buffer);
  if (bytes > *capacity) {
    glBufferData(target, bytes, data, GL_DYNAMIC_DRAW);
    *capacity = bytes;
  } else {
    glBufferSubData(target, 0, bytes, data);
  }
}

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

  // Core profile draws nothing without a vertex array object.
  glGenVertexArrays(1, &vertex_array_);
  glGenBuffers(1, &position_buffer_);
  glGenBuffers(1, &normal_buffer_);
  glGenBuffers(1, &index_buffer_);
  glBindVertexArray(vertex_array_);
  glBindBuffer(GL_ARRAY_BUFFER, position_buffer_);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
  glEnableVertexAttribArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, normal_buffer_);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_buffer_);  // recorded in the VAO
  glBindVertexArray(0);
}

MeshRenderer::~MeshRenderer() {
  glDeleteBuffers(1, &index_buffer_);
  glDeleteBuffers(1, &normal_buffer_);
  glDeleteBuffers(1, &position_buffer_);
  glDeleteVertexArrays(1, &vertex_array_);
}

void MeshRenderer::Clear(const Eigen::Vector3f& rgb) {
  glClearColor(rgb.x(), rgb.y(), rgb.z(), 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

void MeshRenderer::Draw(const VerticesF& positions, const VerticesF& normals,
                        const TrianglesU& triangles, const CameraMatrices& camera,
                        const Material& material) {
  // validate: GL would read out of bounds on a bad index
  ThrowUnless(normals.rows() == positions.rows(), "MeshRenderer::Draw: ", positions.rows(),
              " positions but ", normals.rows(), " normals");
  if (triangles.size() > 0) {
    ThrowUnless(triangles.maxCoeff() < positions.rows(), "MeshRenderer::Draw: index ",
                triangles.maxCoeff(), " out of range for ", positions.rows(), " vertices");
  }
  if (triangles.rows() == 0) return;

  // upload
  glBindVertexArray(vertex_array_);
  Upload(GL_ARRAY_BUFFER, position_buffer_, positions.data(),
         static_cast<long>(positions.size() * sizeof(float)), &position_capacity_);
  Upload(GL_ARRAY_BUFFER, normal_buffer_, normals.data(),
         static_cast<long>(normals.size() * sizeof(float)), &normal_capacity_);
  Upload(GL_ELEMENT_ARRAY_BUFFER, index_buffer_, triangles.data(),
         static_cast<long>(triangles.size() * sizeof(uint32_t)), &index_capacity_);

  // draw (Eigen's default column-major storage is what GL expects: no transpose)
  program_->Use();
  glUniformMatrix4fv(u_view_, 1, GL_FALSE, camera.view.data());
  glUniformMatrix4fv(u_projection_, 1, GL_FALSE, camera.projection.data());
  glUniform3fv(u_albedo_, 1, material.albedo.data());
  glUniform1f(u_ambient_, material.ambient);
  glUniform1f(u_specular_, material.specular);
  glUniform1f(u_shininess_, material.shininess);
  glEnable(GL_DEPTH_TEST);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(triangles.size()), GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);

  const GLenum error = glGetError();
  if (error != GL_NO_ERROR) throw std::runtime_error(Cat("GL error 0x", std::hex, error, " in Draw"));
}

}  // namespace viscera::render
