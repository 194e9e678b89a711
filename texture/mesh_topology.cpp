#include "texture/mesh_topology.h"

#include <Eigen/Geometry>
#include <utility>

#include "core/mesh_connectivity.h"

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

  VertexFaces around = vertex_faces(mesh);
  t.vertex_face_offsets = std::move(around.offsets);
  t.vertex_faces = std::move(around.faces);
  t.face_neighbors = face_neighbors(mesh_edges(mesh), mesh.faces.size());
  return t;
}

}  // namespace hos::texture
