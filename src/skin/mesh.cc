#include "skin/mesh.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <sstream>

#include "common/check.h"

namespace viscera::skin {

void ComputeVertexNormals(Mesh* mesh) {
  mesh->normals.assign(mesh->positions.size(), Vec3::Zero());
  for (const Eigen::Vector3i& t : mesh->triangles) {
    const Vec3& a = mesh->positions[t[0]];
    // Unnormalized cross product = twice the area times the unit normal: area weighting.
    const Vec3 n = (mesh->positions[t[1]] - a).cross(mesh->positions[t[2]] - a);
    for (int k = 0; k < 3; ++k) mesh->normals[t[k]] += n;
  }
  for (Vec3& n : mesh->normals) {
    const double len = n.norm();
    if (len > 0.0) n /= len;
  }
}

namespace {

bool EndsWith(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  std::string tail = s.substr(s.size() - suffix.size());
  std::transform(tail.begin(), tail.end(), tail.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return tail == suffix;
}

void WriteObj(std::ofstream& out, const Mesh& mesh) {
  out << "# viscera skin mesh: " << mesh.num_vertices() << " vertices, " << mesh.num_triangles()
      << " triangles\n";
  const bool has_normals = mesh.normals.size() == mesh.positions.size();
  char line[128];
  for (const Vec3& p : mesh.positions) {
    std::snprintf(line, sizeof(line), "v %.7g %.7g %.7g\n", p.x(), p.y(), p.z());
    out << line;
  }
  if (has_normals) {
    for (const Vec3& n : mesh.normals) {
      std::snprintf(line, sizeof(line), "vn %.5f %.5f %.5f\n", n.x(), n.y(), n.z());
      out << line;
    }
  }
  for (const Eigen::Vector3i& t : mesh.triangles) {
    if (has_normals) {
      std::snprintf(line, sizeof(line), "f %d//%d %d//%d %d//%d\n", t[0] + 1, t[0] + 1, t[1] + 1,
                    t[1] + 1, t[2] + 1, t[2] + 1);
    } else {
      std::snprintf(line, sizeof(line), "f %d %d %d\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    out << line;
  }
}

void WritePly(std::ofstream& out, const Mesh& mesh) {
  const bool has_normals = mesh.normals.size() == mesh.positions.size();
  out << "ply\nformat binary_little_endian 1.0\ncomment viscera skin mesh\n"
      << "element vertex " << mesh.num_vertices() << "\n"
      << "property float x\nproperty float y\nproperty float z\n";
  if (has_normals) out << "property float nx\nproperty float ny\nproperty float nz\n";
  out << "element face " << mesh.num_triangles() << "\n"
      << "property list uchar int vertex_indices\nend_header\n";
  // Binary little-endian: every platform viscera targets is little-endian.
  for (int i = 0; i < mesh.num_vertices(); ++i) {
    float v[6];
    for (int k = 0; k < 3; ++k) v[k] = static_cast<float>(mesh.positions[i][k]);
    if (has_normals) {
      for (int k = 0; k < 3; ++k) v[3 + k] = static_cast<float>(mesh.normals[i][k]);
    }
    out.write(reinterpret_cast<const char*>(v), sizeof(float) * (has_normals ? 6 : 3));
  }
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const unsigned char three = 3;
    const int32_t idx[3] = {t[0], t[1], t[2]};
    out.write(reinterpret_cast<const char*>(&three), 1);
    out.write(reinterpret_cast<const char*>(idx), sizeof(idx));
  }
}

}  // namespace

void WriteMesh(const std::string& path, const Mesh& mesh) {
  const bool obj = EndsWith(path, ".obj");
  const bool ply = EndsWith(path, ".ply");
  ThrowUnless(obj || ply, "mesh export path must end in .obj or .ply, got '", path, "'");
  std::ofstream out(path, std::ios::binary);
  ThrowUnless(out.good(), "cannot open '", path, "' for writing");
  if (obj) {
    WriteObj(out, mesh);
  } else {
    WritePly(out, mesh);
  }
  ThrowUnless(out.good(), "failed writing mesh to '", path, "'");
}

Mesh ReadObj(const std::string& path) {
  std::ifstream in(path);
  ThrowUnless(in.good(), "cannot open '", path, "'");
  Mesh mesh;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "v") {
      Vec3 p;
      ls >> p.x() >> p.y() >> p.z();
      mesh.positions.push_back(p);
    } else if (tag == "f") {
      Eigen::Vector3i t;
      for (int k = 0; k < 3; ++k) {
        std::string word;
        ls >> word;
        t[k] = std::stoi(word.substr(0, word.find('/'))) - 1;
        ThrowUnless(t[k] >= 0, "bad face index in '", path, "': ", line);
      }
      mesh.triangles.push_back(t);
    }
  }
  for (const Eigen::Vector3i& t : mesh.triangles) {
    ThrowUnless(t.maxCoeff() < mesh.num_vertices(), "face index out of range in '", path, "'");
  }
  ComputeVertexNormals(&mesh);
  return mesh;
}

TopologyReport CheckTopology(const Mesh& mesh) {
  TopologyReport report;
  // Directed half-edges (from, to) sorted by their undirected key.
  struct HalfEdge {
    int lo, hi, face;
    bool forward;  // from == lo
  };
  std::vector<HalfEdge> edges;
  edges.reserve(mesh.triangles.size() * 3);
  const int num_faces = mesh.num_triangles();
  for (int f = 0; f < num_faces; ++f) {
    const Eigen::Vector3i& t = mesh.triangles[f];
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      ++report.degenerate_triangles;
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const int a = t[k], b = t[(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), f, a < b});
    }
  }
  std::sort(edges.begin(), edges.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.lo != y.lo ? x.lo < y.lo : x.hi < y.hi;
  });
  // Union-find over faces for the component count.
  std::vector<int> parent(num_faces);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&parent](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  const int num_edges = static_cast<int>(edges.size());
  for (int i = 0; i < num_edges;) {
    int j = i + 1;
    while (j < num_edges && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
    const int count = j - i;
    if (count == 1) ++report.boundary_edges;
    if (count > 2) ++report.nonmanifold_edges;
    if (count == 2 && edges[i].forward == edges[i + 1].forward) ++report.misoriented_edges;
    const int root = find(edges[i].face);
    for (int k = i + 1; k < j; ++k) parent[find(edges[k].face)] = root;
    i = j;
  }
  for (int f = 0; f < num_faces; ++f) {
    if (find(f) == f) ++report.components;
  }
  return report;
}

double SignedVolume(const Mesh& mesh) {
  double six_v = 0.0;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    six_v += mesh.positions[t[0]].dot(mesh.positions[t[1]].cross(mesh.positions[t[2]]));
  }
  return six_v / 6.0;
}

}  // namespace viscera::skin
