#include "render/skin_culling.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/check.h"

namespace viscera::render {

Frustum::Frustum(const Eigen::Matrix4f& m) {
  // Gribb and Hartmann: a clip-space point is inside when -w <= x, y, z <= w
  const Eigen::Vector4f w = m.row(3).transpose();
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::Vector4f r = m.row(axis).transpose();
    planes_[2 * axis] = w + r;
    planes_[2 * axis + 1] = w - r;
  }
}

bool Frustum::Outside(const Eigen::AlignedBox3f& box) const {
  for (const Eigen::Vector4f& p : planes_) {
    // the corner furthest along the plane's normal
    const Eigen::Vector3f corner((p.x() >= 0.0f ? box.max() : box.min()).x(),
                                 (p.y() >= 0.0f ? box.max() : box.min()).y(),
                                 (p.z() >= 0.0f ? box.max() : box.min()).z());
    if (p.head<3>().dot(corner) + p.w() < 0.0f) return true;
  }
  return false;
}

void SkinVertices::Begin(const skin::Mesh& mesh, double length, double radius, TriMesh* out) {
  mesh_ = &mesh;
  out_ = out;
  length_ = length;
  radius_ = radius;
  on_tissue_ = mesh.surface.size() == mesh.positions.size();
  if (radius != angles_radius_) angles_.fill(Angle{});
  angles_radius_ = radius;
  remap_.assign(mesh.positions.size(), -1);
  out->texture.resize(out->positions.size(), Eigen::Vector3f::Zero());
  base_ = static_cast<int32_t>(out->positions.size());
}

int32_t SkinVertices::Copy(int v) {
  const auto at = static_cast<int32_t>(out_->positions.size()) - base_;
  out_->positions.push_back(mesh_->positions[v].cast<float>());
  out_->normals.push_back(mesh_->normals[v].cast<float>());
  if (on_tissue_) {
    // AppendSkin's texture space: the tube unrolled
    const Eigen::Vector2d& sa = mesh_->surface[v];
    // the ring-based skins repeat a few angles (2 pi side / sides): each one's cosine and sine
    // are computed once
    uint64_t bits = 0;
    std::memcpy(&bits, &sa.y(), sizeof bits);
    Angle& angle = angles_[(bits ^ (bits >> 29) ^ (bits >> 47)) % angles_.size()];
    if (!angle.set || angle.bits != bits) {
      angle = {true, bits, radius_ * std::cos(sa.y()), radius_ * std::sin(sa.y())};
    }
    out_->texture.emplace_back(static_cast<float>(sa.x() * length_), static_cast<float>(angle.cos),
                               static_cast<float>(angle.sin));
  } else {
    out_->texture.push_back(out_->positions.back());
  }
  return at;
}

SkinCuller::SkinCuller(int chunk_triangles) : chunk_triangles_(chunk_triangles) {
  VISCERA_DEMAND(chunk_triangles >= 1);
}

CullCounts SkinCuller::Append(const skin::Mesh& mesh, double length, double radius,
                              const CameraMatrices& camera, TriMesh* out) {
  const Frustum frustum(camera.projection * camera.view);
  const Eigen::Vector4f depth_row = -camera.view.row(2).transpose();  // view -z: in front
  const int num_triangles = mesh.num_triangles();
  CullCounts counts;
  counts.triangles = num_triangles;
  visible_.clear();
  for (int first = 0; first < num_triangles; first += chunk_triangles_) {
    Chunk c;
    c.first = first;
    c.count = std::min(chunk_triangles_, num_triangles - first);
    Eigen::AlignedBox3f box;
    for (int t = first; t < first + c.count; ++t) {
      for (int k = 0; k < 3; ++k) box.extend(mesh.positions[mesh.triangles[t][k]].cast<float>());
    }
    ++counts.chunks;
    if (frustum.Outside(box)) continue;
    c.depth = depth_row.head<3>().dot(box.center()) + depth_row.w();
    visible_.push_back(c);
  }
  std::sort(visible_.begin(), visible_.end(),
            [](const Chunk& a, const Chunk& b) { return a.depth < b.depth; });

  vertices_.Begin(mesh, length, radius, out);
  for (const Chunk& c : visible_) {
    ++counts.chunks_drawn;
    counts.triangles_drawn += c.count;
    for (int t = c.first; t < c.first + c.count; ++t) {
      for (int k = 0; k < 3; ++k) out->indices.push_back(vertices_(mesh.triangles[t][k]));
    }
  }
  return counts;
}

}  // namespace viscera::render
