#include "refine/edge_split.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <unordered_map>

namespace hos::refine {
namespace {

// The mesh's undirected edges, and per face the edge of each corner pair
// (corner c to corner c + 1).
struct EdgeTable {
  std::vector<std::pair<int, int>> ends;
  std::vector<std::array<int, 3>> face_edges;
};

EdgeTable edge_table(const TriangleMesh& mesh) {
  EdgeTable table;
  table.face_edges.resize(mesh.faces.size());
  std::unordered_map<std::uint64_t, int> index;
  index.reserve(mesh.faces.size() * 2);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int a = mesh.faces[f][c], b = mesh.faces[f][(c + 1) % 3];
      const std::uint64_t key =
          (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
      const auto [it, added] = index.emplace(key, static_cast<int>(table.ends.size()));
      if (added) table.ends.emplace_back(a, b);
      table.face_edges[f][c] = it->second;
    }
  }
  return table;
}

// Which edges to split: those above their limit, at most `allowed` of them
// (the furthest above first).
std::vector<char> edges_over_limit(const TriangleMesh& mesh,
                                   const EdgeTable& table,
                                   const std::vector<float>& limit,
                                   std::size_t allowed,
                                   bool* budget_reached) {
  std::vector<std::pair<float, int>> over;
  for (std::size_t e = 0; e < table.ends.size(); ++e) {
    const auto [a, b] = table.ends[e];
    const float ratio = (mesh.vertices[a] - mesh.vertices[b]).norm() / std::min(limit[a], limit[b]);
    if (ratio > 1.0f) over.emplace_back(ratio, static_cast<int>(e));
  }
  *budget_reached = over.size() > allowed;
  if (*budget_reached) {
    std::nth_element(over.begin(), over.begin() + static_cast<std::ptrdiff_t>(allowed), over.end(), std::greater<>());
    over.resize(allowed);
  }
  std::vector<char> split(table.ends.size(), 0);
  for (const auto& [ratio, e] : over) split[e] = 1;
  return split;
}

// Red-green closure: a face with two split edges has its third split too, so
// every face is split into four or two or not at all.
void close_red_green(const EdgeTable& table, std::vector<char>& split) {
  for (bool changed = true; changed;) {
    changed = false;
    for (const std::array<int, 3>& edges : table.face_edges) {
      if (split[edges[0]] + split[edges[1]] + split[edges[2]] == 2) {
        for (int e : edges) split[e] = 1;
        changed = true;
      }
    }
  }
}

// Faces after splitting: four for a face with three split edges, two for
// one with a single split edge.
std::size_t split_face_count(const EdgeTable& table, const std::vector<char>& split) {
  std::size_t faces = 0;
  for (const std::array<int, 3>& edges : table.face_edges) {
    const int count = split[edges[0]] + split[edges[1]] + split[edges[2]];
    faces += count == 3 ? 4 : (count == 1 ? 2 : 1);
  }
  return faces;
}

// Appends the midpoint of edge (a, b), with the mean of its attributes.
int add_midpoint(TriangleMesh& out, int a, int b) {
  out.vertices.push_back(0.5f * (out.vertices[a] + out.vertices[b]));
  if (!out.normals.empty()) {
    const Eigen::Vector3f n = out.normals[a] + out.normals[b];
    out.normals.push_back(n.squaredNorm() > 0.0f ? n.normalized() : n);
  }
  if (!out.colors.empty()) {
    Rgb8 c;
    for (int k = 0; k < 3; ++k) c[k] = static_cast<std::uint8_t>((out.colors[a][k] + out.colors[b][k] + 1) / 2);
    out.colors.push_back(c);
  }
  for (auto& [name, values] : out.vertex_scalars) values.push_back(0.5f * (values[a] + values[b]));
  return static_cast<int>(out.vertices.size()) - 1;
}

}  // namespace

EdgeSplitResult split_long_edges(const TriangleMesh& mesh, const std::vector<float>& limit, std::size_t max_faces) {
  EdgeSplitResult result;
  // Step 1: the edges to split. Each split edge adds about two faces.
  const EdgeTable table = edge_table(mesh);
  std::size_t allowed = max_faces > mesh.faces.size() ? (max_faces - mesh.faces.size()) / 2 : 0;
  std::vector<char> split;
  for (;;) {
    split = edges_over_limit(mesh, table, limit, allowed, &result.budget_reached);
    close_red_green(table, split);
    // The closure adds edges: fewer of the long ones until the faces fit.
    const std::size_t faces = split_face_count(table, split);
    if (faces <= max_faces || allowed == 0) break;
    allowed -= std::min(allowed, (faces - max_faces) / 2 + 1);
    result.budget_reached = true;
  }
  // Step 2: their midpoints.
  TriangleMesh& out = result.mesh;
  out = mesh;
  std::vector<int> midpoint(table.ends.size(), -1);
  for (std::size_t e = 0; e < table.ends.size(); ++e) {
    if (!split[e]) continue;
    midpoint[e] = add_midpoint(out, table.ends[e].first, table.ends[e].second);
    ++result.split_edges;
  }
  // Step 3: the faces, each in the orientation of its parent.
  out.faces.clear();
  out.faces.reserve(mesh.faces.size() + 2 * static_cast<std::size_t>(result.split_edges));
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Eigen::Vector3i& v = mesh.faces[f];
    const std::array<int, 3>& e = table.face_edges[f];
    const int count = split[e[0]] + split[e[1]] + split[e[2]];
    if (count == 0) {
      out.faces.push_back(v);
    } else if (count == 3) {
      const int m01 = midpoint[e[0]], m12 = midpoint[e[1]], m20 = midpoint[e[2]];
      out.faces.emplace_back(v[0], m01, m20);
      out.faces.emplace_back(m01, v[1], m12);
      out.faces.emplace_back(m20, m12, v[2]);
      out.faces.emplace_back(m01, m12, m20);
    } else {
      const int c = split[e[0]] ? 0 : (split[e[1]] ? 1 : 2);
      const int m = midpoint[e[c]];
      out.faces.emplace_back(v[c], m, v[(c + 2) % 3]);
      out.faces.emplace_back(m, v[(c + 1) % 3], v[(c + 2) % 3]);
    }
  }
  return result;
}

}  // namespace hos::refine
