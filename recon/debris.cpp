#include "recon/debris.h"

#include <Eigen/Geometry>
#include <algorithm>

#include "core/mesh_connectivity.h"
#include "recon/trim.h"

namespace hos::recon {
namespace {

double face_area(const TriangleMesh& mesh, const Eigen::Vector3i& f) {
  const Eigen::Vector3d a = mesh.vertices[f[0]].cast<double>();
  const Eigen::Vector3d b = mesh.vertices[f[1]].cast<double>();
  const Eigen::Vector3d c = mesh.vertices[f[2]].cast<double>();
  return 0.5 * (b - a).cross(c - a).norm();
}

}  // namespace

DebrisReport remove_debris(TriangleMesh& mesh, const DebrisOptions& options) {
  DebrisReport report;
  const MeshPieces pieces = connected_pieces(mesh);
  const std::vector<int>& piece = pieces.face_piece;
  report.components = static_cast<std::size_t>(pieces.count);
  std::vector<double> area(static_cast<std::size_t>(pieces.count), 0.0);
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) area[piece[i]] += face_area(mesh, mesh.faces[i]);
  const double largest = area.empty() ? 0.0 : *std::max_element(area.begin(), area.end());
  std::vector<char> debris(area.size(), 0);
  for (std::size_t p = 0; p < area.size(); ++p) {
    debris[p] = options.remove && area[p] < options.min_area_fraction * largest;
    if (debris[p]) {
      ++report.components_removed;
      report.area_removed += area[p];
    } else {
      report.area_kept += area[p];
    }
  }
  if (report.components_removed == 0) return report;
  std::vector<Eigen::Vector3i> kept;
  kept.reserve(mesh.faces.size());
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
    if (!debris[piece[i]]) kept.push_back(mesh.faces[i]);
  }
  report.faces_removed = mesh.faces.size() - kept.size();
  mesh.faces.swap(kept);
  remove_unreferenced_vertices(mesh);
  return report;
}

}  // namespace hos::recon
