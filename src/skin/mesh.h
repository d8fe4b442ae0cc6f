#pragma once
/// The indexed triangle mesh every skin produces, its normals, export (OBJ / PLY) and the
/// topology / volume checks the tests and tools use.
#include <string>
#include <vector>

#include "common/types.h"

namespace viscera::skin {

/// Indexed triangle mesh. Triangles are counter-clockwise seen from outside (outward
/// normals). Buffers are std::vectors so that clear() + push_back keeps their capacity:
/// a skin rebuilding the same-sized mesh every frame allocates nothing.
struct Mesh {
  std::vector<Vec3> positions;             ///< #V, metres
  std::vector<Vec3> normals;               ///< #V unit vectors (or zero for isolated vertices)
  std::vector<Eigen::Vector3i> triangles;  ///< #F vertex indices
  /// Per vertex, where it sits on the tissue: (s, angle), the curve parameter in [0, 1] and the
  /// angle (rad) around the centre line from the ring frame's normal. Filled by the ring-based
  /// skins (#V), empty for the others; the renderer anchors its procedural textures to it, so
  /// the serosa's vessels move with the bowel.
  std::vector<Eigen::Vector2d> surface;
  /// The ring-based skins' tube (tube_rays.h): `rings` rings of `sides` vertices from vertex
  /// `first_vertex` on, ring after ring, side j at angle 2 pi j / sides; the triangles from
  /// `first_triangle` on join ring i to ring i + 1, 2 sides of them per pair of rings, and the
  /// others are the end caps (their last rings of the same sides). rings == 0: no such layout
  /// (the implicit skin). The renderer coarsens the far parts of the tube with it.
  struct TubeGrid {
    int rings = 0, sides = 0, first_vertex = 0, first_triangle = 0;
  } tube;

  int num_vertices() const { return static_cast<int>(positions.size()); }
  int num_triangles() const { return static_cast<int>(triangles.size()); }
  void Clear() {
    positions.clear();
    normals.clear();
    triangles.clear();
    surface.clear();
    tube = {};
  }
};

/// Area-weighted vertex normals from the triangles (each face adds its unnormalized cross
/// product to its three vertices), normalized. Resizes mesh->normals to #V.
void ComputeVertexNormals(Mesh* mesh);

/// Writes the mesh as Wavefront OBJ (".obj": v, vn, f with 1-based v//vn) or binary little-
/// endian PLY (".ply": float x y z nx ny nz, uchar-count int faces), chosen by extension.
/// @throws InputError for another extension or a file that cannot be written.
void WriteMesh(const std::string& path, const Mesh& mesh);

/// Reads back an OBJ written by WriteMesh (v and f lines; normals recomputed). For tests and
/// tools. @throws InputError if the file cannot be read or is malformed.
Mesh ReadObj(const std::string& path);

/// Topology of a triangle mesh seen as a surface.
struct TopologyReport {
  int boundary_edges = 0;        ///< undirected edges used by exactly one triangle
  int nonmanifold_edges = 0;     ///< undirected edges used by three or more triangles
  int misoriented_edges = 0;     ///< edges shared by two triangles traversing it the same way
  int degenerate_triangles = 0;  ///< triangles repeating a vertex index
  int components = 0;            ///< connected components (through shared edges)
  /// Closed, 2-manifold, consistently oriented: every edge used exactly twice, once in each
  /// direction.
  bool closed_oriented_manifold() const {
    return boundary_edges == 0 && nonmanifold_edges == 0 && misoriented_edges == 0 &&
           degenerate_triangles == 0;
  }
};

/// Edge-based topology check, O(F log F).
TopologyReport CheckTopology(const Mesh& mesh);

/// Signed enclosed volume by the divergence theorem, sum over faces of (a . (b x c)) / 6 (m^3).
/// Positive for a closed mesh with outward orientation.
double SignedVolume(const Mesh& mesh);

}  // namespace viscera::skin
