#include "texture/charts.h"

#include <unordered_map>

namespace hos::texture {

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
