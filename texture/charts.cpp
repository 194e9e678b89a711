#include "texture/charts.h"

#include <algorithm>
#include <map>
#include <unordered_map>

namespace hos::texture {

namespace {

// A merge may not cost more than half the photo pixels (blurrier texels).
constexpr double kMinAreaRatio = 0.5;

// Connected groups of edge-adjacent faces with the same label (>= 0).
std::vector<std::vector<int>> label_components(const MeshTopology& topology, const std::vector<int>& labels) {
  const int num_faces = static_cast<int>(labels.size());
  std::vector<char> seen(num_faces, 0);
  std::vector<std::vector<int>> components;
  std::vector<int> stack;
  for (int seed = 0; seed < num_faces; ++seed) {
    if (labels[seed] < 0 || seen[seed]) continue;
    seen[seed] = 1;
    std::vector<int> faces;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      faces.push_back(f);
      for (int g : topology.face_neighbors[f]) {
        if (g >= 0 && !seen[g] && labels[g] == labels[seed]) {
          seen[g] = 1;
          stack.push_back(g);
        }
      }
    }
    components.push_back(std::move(faces));
  }
  return components;
}

// The projected area of face f in view (0 if the view is no candidate).
float projected_area(const FaceViewCandidates& candidates, int f, int view) {
  for (int i = candidates.begin(f); i < candidates.end(f); ++i) {
    if (candidates.samples[i].view == view) return std::max(candidates.samples[i].projected_area_px, 1e-6f);
  }
  return 0.0f;
}

// The view a small chart should take, or -1.
int merge_target(const MeshTopology& topology,
                 const FaceViewCandidates& candidates,
                 const std::vector<int>& faces,
                 const std::vector<int>& labels,
                 double own_area) {
  const int own = labels[faces.front()];
  std::map<int, int> shared_edges;  // neighbouring view -> edges
  for (int f : faces) {
    for (int g : topology.face_neighbors[f]) {
      if (g >= 0 && labels[g] >= 0 && labels[g] != own) ++shared_edges[labels[g]];
    }
  }
  std::vector<std::pair<int, int>> order(shared_edges.begin(), shared_edges.end());
  std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  for (const auto& [view, edges] : order) {
    double area = 0.0;
    bool everywhere = true;
    for (int f : faces) {
      const float a = projected_area(candidates, f, view);
      everywhere = everywhere && a > 0.0f;
      area += a;
    }
    if (everywhere && area >= kMinAreaRatio * own_area) return view;
  }
  return -1;
}

// A chart no single neighbour can take whole: its faces go, from the border
// inwards, to a neighbouring face's view wherever that view sees them (at no
// less than half the area). Returns whether any face changed.
bool erode_chart(const MeshTopology& topology,
                 const FaceViewCandidates& candidates,
                 const std::vector<int>& faces,
                 std::vector<int>& labels) {
  const int own = labels[faces.front()];
  bool changed = false, progress = true;
  while (progress) {
    progress = false;
    for (int f : faces) {
      if (labels[f] != own) continue;
      const float own_area = projected_area(candidates, f, own);
      for (int g : topology.face_neighbors[f]) {
        if (g < 0 || labels[g] < 0 || labels[g] == own) continue;
        if (projected_area(candidates, f, labels[g]) >= kMinAreaRatio * own_area) {
          labels[f] = labels[g];
          progress = changed = true;
          break;
        }
      }
    }
  }
  return changed;
}

}  // namespace

int merge_small_charts(const MeshTopology& topology,
                       const FaceViewCandidates& candidates,
                       double min_chart_area_px,
                       std::vector<int>& labels) {
  int merged = 0;
  for (int pass = 0; pass < 4 && min_chart_area_px > 0.0; ++pass) {
    std::vector<std::vector<int>> components = label_components(topology, labels);
    std::vector<std::pair<double, int>> small;  // (area, component)
    for (std::size_t c = 0; c < components.size(); ++c) {
      double area = 0.0;
      for (int f : components[c]) area += projected_area(candidates, f, labels[f]);
      if (area < min_chart_area_px) small.emplace_back(area, static_cast<int>(c));
    }
    std::sort(small.begin(), small.end());
    int merged_now = 0;
    for (const auto& [area, c] : small) {
      const int view = merge_target(topology, candidates, components[c], labels, area);
      if (view >= 0) {
        for (int f : components[c]) labels[f] = view;
        ++merged_now;
      } else if (erode_chart(topology, candidates, components[c], labels)) {
        ++merged_now;
      }
    }
    merged += merged_now;
    if (merged_now == 0) break;
  }
  return merged;
}

std::vector<Chart> build_charts(const TriangleMesh& mesh,
                                const MeshTopology& topology,
                                const std::vector<int>& labels) {
  const int num_faces = static_cast<int>(mesh.faces.size());
  std::vector<int> chart_of(num_faces, -1);
  std::vector<Chart> charts;
  std::vector<int> stack;
  std::vector<int> local_index(mesh.vertices.size(), -1);
  for (int seed = 0; seed < num_faces; ++seed) {
    if (labels[seed] < 0 || chart_of[seed] >= 0) continue;
    Chart chart;
    chart.view = labels[seed];
    const int id = static_cast<int>(charts.size());
    chart_of[seed] = id;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      chart.faces.push_back(f);
      for (int g : topology.face_neighbors[f]) {
        if (g >= 0 && chart_of[g] < 0 && labels[g] == chart.view) {
          chart_of[g] = id;
          stack.push_back(g);
        }
      }
    }
    for (int f : chart.faces) {
      Eigen::Vector3i local;
      for (int c = 0; c < 3; ++c) {
        const int v = mesh.faces[f][c];
        if (local_index[v] < 0) {
          local_index[v] = static_cast<int>(chart.vertices.size());
          chart.vertices.push_back(v);
        }
        local[c] = local_index[v];
      }
      chart.local_faces.push_back(local);
    }
    for (int v : chart.vertices) local_index[v] = -1;
    charts.push_back(std::move(chart));
  }
  return charts;
}

}  // namespace hos::texture
