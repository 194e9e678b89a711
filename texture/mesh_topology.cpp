#include "texture/mesh_topology.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>

namespace hos::texture {

MeshTopology build_topology(const TriangleMesh& mesh) {
  const int num_faces = static_cast<int>(mesh.faces.size());
  const int num_vertices = static_cast<int>(mesh.vertices.size());
  MeshTopology t;
  t.face_normals.resize(num_faces);
  t.face_areas.resize(num_faces);
  t.vertex_normals.assign(num_vertices, Eigen::Vector3f::Zero());
  for (int f = 0; f < num_faces; ++f) {
    const auto& face = mesh.faces[f];
    const Eigen::Vector3f n =
        (mesh.vertices[face[1]] - mesh.vertices[face[0]]).cross(mesh.vertices[face[2]] - mesh.vertices[face[0]]);
    const float len = n.norm();
    t.face_areas[f] = 0.5f * len;
    t.face_normals[f] = len > 0.0f ? Eigen::Vector3f(n / len) : Eigen::Vector3f::Zero();
    for (int c = 0; c < 3; ++c) t.vertex_normals[face[c]] += n;
  }
  for (auto& n : t.vertex_normals) {
    const float len = n.norm();
    n = len > 0.0f ? Eigen::Vector3f(n / len) : Eigen::Vector3f(0.0f, 0.0f, 1.0f);
  }

  t.vertex_face_offsets.assign(num_vertices + 1, 0);
  for (const auto& face : mesh.faces) {
    for (int c = 0; c < 3; ++c) ++t.vertex_face_offsets[face[c] + 1];
  }
  for (int v = 0; v < num_vertices; ++v) t.vertex_face_offsets[v + 1] += t.vertex_face_offsets[v];
  t.vertex_faces.resize(t.vertex_face_offsets.back());
  {
    std::vector<int> cursor(t.vertex_face_offsets.begin(), t.vertex_face_offsets.end() - 1);
    for (int f = 0; f < num_faces; ++f) {
      for (int c = 0; c < 3; ++c) t.vertex_faces[cursor[mesh.faces[f][c]]++] = f;
    }
  }

  // Edge matching by sorting (min vertex, max vertex, face, corner) records.
  struct EdgeRecord {
    std::uint64_t key;
    int face;
    int corner;
  };
  std::vector<EdgeRecord> edges;
  edges.reserve(3 * static_cast<std::size_t>(num_faces));
  for (int f = 0; f < num_faces; ++f) {
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t a = mesh.faces[f][c];
      const std::uint32_t b = mesh.faces[f][(c + 1) % 3];
      if (a == b) continue;
      const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
      edges.push_back({key, f, c});
    }
  }
  std::sort(edges.begin(), edges.end(),
            [](const EdgeRecord& x, const EdgeRecord& y) { return x.key != y.key ? x.key < y.key : x.face < y.face; });
  t.face_neighbors.assign(num_faces, {-1, -1, -1});
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    for (std::size_t k = i; k + 1 < j; k += 2) {
      const EdgeRecord& x = edges[k];
      const EdgeRecord& y = edges[k + 1];
      if (x.face == y.face) continue;
      t.face_neighbors[x.face][x.corner] = y.face;
      t.face_neighbors[y.face][y.corner] = x.face;
    }
    i = j;
  }
  return t;
}

}  // namespace hos::texture
