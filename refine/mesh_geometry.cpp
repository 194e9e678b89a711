#include "refine/mesh_geometry.h"

#include <Eigen/Geometry>

namespace hos::refine {

std::vector<Eigen::Vector3f> face_area_normals(const TriangleMesh& mesh) {
  std::vector<Eigen::Vector3f> normals(mesh.faces.size());
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
    const Eigen::Vector3i& f = mesh.faces[i];
    const Eigen::Vector3f& a = mesh.vertices[f[0]];
    normals[i] = (mesh.vertices[f[1]] - a).cross(mesh.vertices[f[2]] - a);
  }
  return normals;
}

std::vector<Eigen::Vector3f> vertex_normals(const TriangleMesh& mesh) {
  std::vector<Eigen::Vector3f> normals(mesh.vertices.size(), Eigen::Vector3f::Zero());
  const std::vector<Eigen::Vector3f> face_normals = face_area_normals(mesh);
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
    for (int c = 0; c < 3; ++c) normals[mesh.faces[i][c]] += face_normals[i];
  }
  for (Eigen::Vector3f& n : normals) {
    const float length = n.norm();
    n = length > 0.0f ? Eigen::Vector3f(n / length) : Eigen::Vector3f::Zero();
  }
  return normals;
}

double mean_edge_length(const TriangleMesh& mesh) {
  double sum = 0.0;
  for (const Eigen::Vector3i& f : mesh.faces) {
    for (int c = 0; c < 3; ++c) sum += (mesh.vertices[f[c]] - mesh.vertices[f[(c + 1) % 3]]).norm();
  }
  return mesh.faces.empty() ? 0.0 : sum / (3.0 * static_cast<double>(mesh.faces.size()));
}

}  // namespace hos::refine
