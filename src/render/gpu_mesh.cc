#include "render/gpu_mesh.h"

#include <algorithm>

#include "common/check.h"
#include "render/gl.h"

namespace viscera::render {
namespace {

// Uploads `bytes` into `buffer`, reallocating only when it grows.
void Upload(GLenum target, unsigned buffer, const void* data, long bytes, long* capacity) {
  glBindBuffer(target, buffer);
  if (bytes > *capacity) {
    glBufferData(target, bytes, data, GL_DYNAMIC_DRAW);
    *capacity = bytes;
  } else if (bytes > 0) {
    glBufferSubData(target, 0, bytes, data);
  }
}

}  // namespace

GpuMesh::GpuMesh() {
  // Core profile draws nothing without a vertex array object.
  glGenVertexArrays(1, &vertex_array_);
  glGenBuffers(1, &position_buffer_);
  glGenBuffers(1, &normal_buffer_);
  glGenBuffers(1, &texture_buffer_);
  glGenBuffers(1, &index_buffer_);
  glBindVertexArray(vertex_array_);
  glBindBuffer(GL_ARRAY_BUFFER, position_buffer_);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
  glEnableVertexAttribArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, normal_buffer_);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glBindBuffer(GL_ARRAY_BUFFER, texture_buffer_);
  glVertexAttribPointer(2, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
  glEnableVertexAttribArray(2);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_buffer_);  // recorded in the VAO
  glBindVertexArray(0);
}

GpuMesh::~GpuMesh() {
  glDeleteBuffers(1, &index_buffer_);
  glDeleteBuffers(1, &texture_buffer_);
  glDeleteBuffers(1, &normal_buffer_);
  glDeleteBuffers(1, &position_buffer_);
  glDeleteVertexArrays(1, &vertex_array_);
}

void GpuMesh::Upload(const float* positions, const float* normals, long num_vertices,
                     const uint32_t* indices, long num_indices, const float* texture) {
  // validate: GL would read out of bounds on a bad index
  ThrowUnless(num_indices % 3 == 0, "GpuMesh::Upload: ", num_indices,
              " indices is not whole triangles");
  if (num_indices > 0) {
    const uint32_t largest = *std::max_element(indices, indices + num_indices);
    ThrowUnless(largest < num_vertices, "GpuMesh::Upload: index ", largest, " out of range for ",
                num_vertices, " vertices");
  }
  const long vertex_bytes = num_vertices * 3 * static_cast<long>(sizeof(float));
  glBindVertexArray(vertex_array_);
  render::Upload(GL_ARRAY_BUFFER, position_buffer_, positions, vertex_bytes, &position_capacity_);
  render::Upload(GL_ARRAY_BUFFER, normal_buffer_, normals, vertex_bytes, &normal_capacity_);
  render::Upload(GL_ARRAY_BUFFER, texture_buffer_, texture != nullptr ? texture : positions,
                 vertex_bytes, &texture_capacity_);
  render::Upload(GL_ELEMENT_ARRAY_BUFFER, index_buffer_, indices,
                 num_indices * static_cast<long>(sizeof(uint32_t)), &index_capacity_);
  glBindVertexArray(0);
  num_indices_ = num_indices;
}

void GpuMesh::Upload(const TriMesh& mesh) {
  ThrowUnless(mesh.normals.size() == mesh.positions.size(),
              "GpuMesh::Upload: ", mesh.positions.size(), " positions but ", mesh.normals.size(),
              " normals");
  ThrowUnless(mesh.texture.empty() || mesh.texture.size() == mesh.positions.size(),
              "GpuMesh::Upload: ", mesh.positions.size(), " positions but ", mesh.texture.size(),
              " texture points");
  Upload(mesh.positions.empty() ? nullptr : mesh.positions.front().data(),
         mesh.normals.empty() ? nullptr : mesh.normals.front().data(), mesh.num_vertices(),
         mesh.indices.data(), static_cast<long>(mesh.indices.size()),
         mesh.texture.empty() ? nullptr : mesh.texture.front().data());
}

void GpuMesh::Draw() const {
  if (num_indices_ == 0) return;
  glBindVertexArray(vertex_array_);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(num_indices_), GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
}

}  // namespace viscera::render
