#include "texture/decimate.h"

#include <meshoptimizer.h>

#include <cstdint>
#include <vector>

namespace hos::texture {

TriangleMesh decimate_mesh(const TriangleMesh& mesh, std::size_t max_faces, DecimationStats* stats) {
  DecimationStats local;
  local.faces_before = mesh.faces.size();
  if (mesh.faces.size() <= max_faces) {
    local.faces_after = mesh.faces.size();
    if (stats) *stats = local;
    return mesh;
  }
  std::vector<std::uint32_t> indices;
  indices.reserve(3 * mesh.faces.size());
  for (const auto& f : mesh.faces) {
    for (int c = 0; c < 3; ++c) indices.push_back(static_cast<std::uint32_t>(f[c]));
  }
  std::vector<float> positions;
  positions.reserve(3 * mesh.vertices.size());
  for (const auto& v : mesh.vertices) positions.insert(positions.end(), {v.x(), v.y(), v.z()});
  std::vector<std::uint32_t> simplified(indices.size());
  // A large target error lets the face budget decide.
  const std::size_t count =
      meshopt_simplify(simplified.data(), indices.data(), indices.size(), positions.data(), mesh.vertices.size(),
                       3 * sizeof(float), 3 * max_faces, 1.0f, 0, &local.relative_error);
  simplified.resize(count);

  TriangleMesh out;
  std::vector<int> remap(mesh.vertices.size(), -1);
  for (std::size_t i = 0; i < simplified.size(); i += 3) {
    Eigen::Vector3i face;
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t v = simplified[i + c];
      if (remap[v] < 0) {
        remap[v] = static_cast<int>(out.vertices.size());
        out.vertices.push_back(mesh.vertices[v]);
        if (!mesh.normals.empty()) out.normals.push_back(mesh.normals[v]);
        if (!mesh.colors.empty()) out.colors.push_back(mesh.colors[v]);
      }
      face[c] = remap[v];
    }
    out.faces.push_back(face);
  }
  local.faces_after = out.faces.size();
  if (stats) *stats = local;
  return out;
}

}  // namespace hos::texture
