#include "recon/trim.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace hos::recon {
namespace {

// Samples bucketed in cubic cells of the query radius: a point is near the
// data if some sample in its 27 surrounding cells is within the radius.
class SampleHash {
 public:
  SampleHash(const std::vector<Eigen::Vector3f>& samples, double radius)
      : samples_(samples), cell_(radius), radius2_(radius * radius) {
    for (std::size_t i = 0; i < samples.size(); ++i) cells_[key(cell_of(samples[i]))].push_back(i);
  }

  bool near(const Eigen::Vector3f& x) const { return count_within(x, radius2_, 1) > 0; }

  // Samples within sqrt(radius2) of x, counted up to limit.
  int count_within(const Eigen::Vector3f& x, double radius2, int limit) const {
    const int reach = std::max(1, static_cast<int>(std::ceil(std::sqrt(radius2) / cell_ - 1e-9)));
    const Eigen::Vector3i c = cell_of(x);
    int count = 0;
    for (int dz = -reach; dz <= reach; ++dz) {
      for (int dy = -reach; dy <= reach; ++dy) {
        for (int dx = -reach; dx <= reach; ++dx) {
          const auto it = cells_.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (std::size_t i : it->second) {
            if ((samples_[i] - x).cast<double>().squaredNorm() <= radius2 && ++count >= limit) return count;
          }
        }
      }
    }
    return count;
  }

 private:
  Eigen::Vector3i cell_of(const Eigen::Vector3f& x) const {
    return (x.cast<double>() / cell_).array().floor().cast<int>();
  }
  static std::int64_t key(const Eigen::Vector3i& c) {
    return ((std::int64_t{c.x()} & 0x1FFFFF) << 42) | ((std::int64_t{c.y()} & 0x1FFFFF) << 21) |
           (std::int64_t{c.z()} & 0x1FFFFF);
  }

  const std::vector<Eigen::Vector3f>& samples_;
  double cell_;
  double radius2_;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> cells_;
};

// Sparse but consistent support: a sample with fewer than kSupport others
// within the trim distance, but at least kSupport within sparse_reach times
// it, lies on surface that few samples cover (ground seen at grazing angles,
// a side few photos see); around it the trim distance is sparse_reach times
// longer, so the mesh between such samples stays. An isolated sample (an
// outlier) keeps the plain distance.
constexpr int kSupport = 4;

std::vector<Eigen::Vector3f> sparse_supported_samples(const std::vector<Eigen::Vector3f>& samples,
                                                      const SampleHash& hash,
                                                      double max_distance,
                                                      double sparse_reach) {
  const double near2 = max_distance * max_distance, wide2 = near2 * sparse_reach * sparse_reach;
  const std::int64_t n = static_cast<std::int64_t>(samples.size());
  std::vector<char> sparse(samples.size(), 0);
#pragma omp parallel for schedule(dynamic, 4096)
  for (std::int64_t i = 0; i < n; ++i) {
    // Counts include the sample itself.
    sparse[i] = hash.count_within(samples[i], near2, kSupport + 1) <= kSupport &&
                hash.count_within(samples[i], wide2, kSupport + 1) > kSupport;
  }
  std::vector<Eigen::Vector3f> out;
  for (std::int64_t i = 0; i < n; ++i) {
    if (sparse[i]) out.push_back(samples[i]);
  }
  return out;
}

}  // namespace

std::vector<int> remove_unreferenced_vertices(TriangleMesh& mesh) {
  std::vector<int> remap(mesh.vertices.size(), -1);
  int next = 0;
  for (const auto& f : mesh.faces) {
    for (int c = 0; c < 3; ++c) {
      if (remap[f[c]] < 0) remap[f[c]] = next++;
    }
  }
  const auto compact = [&](auto& values) {
    if (values.empty()) return;
    std::remove_reference_t<decltype(values)> out(next);
    for (std::size_t i = 0; i < remap.size(); ++i) {
      if (remap[i] >= 0) out[remap[i]] = values[i];
    }
    values.swap(out);
  };
  compact(mesh.vertices);
  compact(mesh.normals);
  compact(mesh.colors);
  for (auto& [name, values] : mesh.vertex_scalars) compact(values);
  for (auto& f : mesh.faces) f = Eigen::Vector3i(remap[f[0]], remap[f[1]], remap[f[2]]);
  return remap;
}

std::size_t trim_far_from_samples(TriangleMesh& mesh,
                                  const std::vector<Eigen::Vector3f>& samples,
                                  double max_distance,
                                  double sparse_reach) {
  const SampleHash hash(samples, max_distance);
  const std::vector<Eigen::Vector3f> sparse = sparse_reach > 1.0
                                                  ? sparse_supported_samples(samples, hash, max_distance, sparse_reach)
                                                  : std::vector<Eigen::Vector3f>{};
  const SampleHash sparse_hash(sparse, sparse_reach * max_distance);
  std::vector<char> near(mesh.vertices.size());
  const std::int64_t nv = static_cast<std::int64_t>(mesh.vertices.size());
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::int64_t v = 0; v < nv; ++v) near[v] = hash.near(mesh.vertices[v]) || sparse_hash.near(mesh.vertices[v]);
  std::vector<Eigen::Vector3i> kept;
  kept.reserve(mesh.faces.size());
  for (const auto& f : mesh.faces) {
    if (near[f[0]] || near[f[1]] || near[f[2]]) kept.push_back(f);
  }
  const std::size_t removed = mesh.faces.size() - kept.size();
  mesh.faces.swap(kept);
  remove_unreferenced_vertices(mesh);
  return removed;
}

}  // namespace hos::recon
