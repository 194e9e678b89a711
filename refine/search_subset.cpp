#include "refine/search_subset.h"

namespace hos::refine {

std::vector<int> spaced_vertices(const TriangleMesh& mesh, const VertexRings& rings, const std::vector<float>& radius) {
  const int n = static_cast<int>(mesh.vertices.size());
  std::vector<char> covered(n, 0);
  std::vector<int> reached_by(n, -1);  // the searched vertex whose walk last reached it
  std::vector<int> searched, frontier;
  for (int v = 0; v < n; ++v) {
    if (covered[v]) continue;
    searched.push_back(v);
    covered[v] = 1;
    // Walk outwards along edges while within the radius of v.
    const float r2 = radius[v] * radius[v];
    frontier.assign(1, v);
    reached_by[v] = v;
    while (!frontier.empty()) {
      const int u = frontier.back();
      frontier.pop_back();
      for (int k = rings.offsets[u]; k < rings.offsets[u + 1]; ++k) {
        const int w = rings.neighbors[k];
        if (reached_by[w] == v || (mesh.vertices[w] - mesh.vertices[v]).squaredNorm() >= r2) continue;
        reached_by[w] = v;
        covered[w] = 1;
        frontier.push_back(w);
      }
    }
  }
  return searched;
}

void fill_targets(const VertexRings& rings, const std::vector<char>& searched, std::vector<VertexTarget>& targets) {
  const int n = static_cast<int>(targets.size());
  std::vector<char> known(searched.begin(), searched.end());
  std::vector<int> pending;
  for (int v = 0; v < n; ++v) {
    if (!known[v]) pending.push_back(v);
  }
  // One ring per sweep; each sweep reads only the previous ones' targets, so
  // the result does not depend on the order of the vertices.
  std::vector<VertexTarget> next;
  std::vector<int> reached, still_pending;
  while (!pending.empty()) {
    reached.clear(), still_pending.clear(), next.clear();
    for (int u : pending) {
      double weight = 0.0, weighted_offset = 0.0;
      int count = 0;
      for (int k = rings.offsets[u]; k < rings.offsets[u + 1]; ++k) {
        const int w = rings.neighbors[k];
        if (!known[w]) continue;
        weight += targets[w].weight, weighted_offset += static_cast<double>(targets[w].weight) * targets[w].offset;
        ++count;
      }
      if (count == 0) {
        still_pending.push_back(u);
        continue;
      }
      VertexTarget t;
      t.weight = static_cast<float>(weight / count);
      t.offset = weight > 0.0 ? static_cast<float>(weighted_offset / weight) : 0.0f;
      reached.push_back(u);
      next.push_back(t);
    }
    if (reached.empty()) break;
    for (std::size_t i = 0; i < reached.size(); ++i) {
      targets[reached[i]] = next[i];
      known[reached[i]] = 1;
    }
    pending.swap(still_pending);
  }
}

}  // namespace hos::refine
