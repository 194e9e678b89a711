#include "recon/debris.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <unordered_map>

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

constexpr std::size_t kMinSupportSamples = 50;

// Per piece, the samples within support.distance of its vertices (each
// counted once, for the first such piece found) and their confidence sum;
// only pieces marked in candidate are looked at.
struct PieceSupport {
  std::size_t samples = 0;
  double views = 0.0;
};

std::vector<PieceSupport> support_of_pieces(const TriangleMesh& mesh,
                                            const std::vector<int>& face_piece,
                                            const std::vector<char>& candidate,
                                            const DebrisSupport& support) {
  std::vector<PieceSupport> out(candidate.size());
  const double cell = support.distance, d2 = support.distance * support.distance;
  const auto cell_of = [&](const Eigen::Vector3f& x) -> Eigen::Vector3i {
    return (x.cast<double>() / cell).array().floor().cast<int>();
  };
  const auto key = [](const Eigen::Vector3i& c) {
    return ((std::int64_t{c.x()} & 0x1FFFFF) << 42) | ((std::int64_t{c.y()} & 0x1FFFFF) << 21) |
           (std::int64_t{c.z()} & 0x1FFFFF);
  };
  std::unordered_map<std::int64_t, std::vector<std::pair<int, int>>> cells;  // (vertex, piece)
  std::vector<char> hashed(mesh.vertices.size(), 0);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (!candidate[face_piece[f]]) continue;
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.faces[f][c];
      if (hashed[v]) continue;
      hashed[v] = 1;
      cells[key(cell_of(mesh.vertices[v]))].emplace_back(v, face_piece[f]);
    }
  }
  if (cells.empty()) return out;
  const auto& points = *support.points;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3i c = cell_of(points[i]);
    int found = -1;
    for (int dz = -1; dz <= 1 && found < 0; ++dz) {
      for (int dy = -1; dy <= 1 && found < 0; ++dy) {
        for (int dx = -1; dx <= 1 && found < 0; ++dx) {
          const auto it = cells.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells.end()) continue;
          for (const auto& [v, p] : it->second) {
            if ((mesh.vertices[v] - points[i]).cast<double>().squaredNorm() <= d2) {
              found = p;
              break;
            }
          }
        }
      }
    }
    if (found < 0) continue;
    ++out[found].samples;
    out[found].views += (*support.views)[i];
  }
  return out;
}

}  // namespace

DebrisReport remove_debris(TriangleMesh& mesh, const DebrisOptions& options, const DebrisSupport& support) {
  DebrisReport report;
  const MeshPieces pieces = connected_pieces(mesh);
  const std::vector<int>& piece = pieces.face_piece;
  report.components = static_cast<std::size_t>(pieces.count);
  std::vector<double> area(static_cast<std::size_t>(pieces.count), 0.0);
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) area[piece[i]] += face_area(mesh, mesh.faces[i]);
  const double largest = area.empty() ? 0.0 : *std::max_element(area.begin(), area.end());
  std::vector<char> debris(area.size(), 0);
  for (std::size_t p = 0; p < area.size(); ++p)
    debris[p] = options.remove && area[p] < options.min_area_fraction * largest;
  const bool by_support = options.keep_min_views > 0.0 && support.points && support.views &&
                          support.views->size() == support.points->size() && support.distance > 0.0;
  if (by_support) {
    const std::vector<PieceSupport> s = support_of_pieces(mesh, piece, debris, support);
    for (std::size_t p = 0; p < area.size(); ++p) {
      if (debris[p] && s[p].samples >= kMinSupportSamples &&
          s[p].views >= options.keep_min_views * static_cast<double>(s[p].samples)) {
        debris[p] = 0;
        ++report.components_kept_by_support;
      }
    }
  }
  for (std::size_t p = 0; p < area.size(); ++p) {
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
