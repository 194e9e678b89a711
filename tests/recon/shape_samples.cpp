#include "tests/recon/shape_samples.h"

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <numeric>
#include <set>

namespace hos::recon::testing {

GridGeometry cube_grid(int n, double h) {
  GridGeometry g;
  g.dims = Eigen::Vector3i::Constant(n);
  g.spacing = h;
  return g;
}

namespace {

void add(PointCloud& c, const Eigen::Vector3d& p, const Eigen::Vector3d& n, double noise,
         std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, noise);
  c.positions.push_back((p + (noise > 0 ? g(rng) : 0.0) * n).cast<float>());
  c.normals.push_back(n.cast<float>());
}

}  // namespace

PointCloud sample_sphere(int n, double radius, double noise, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  PointCloud c;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d d = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    add(c, radius * d, d, noise, rng);
  }
  return c;
}

PointCloud sample_torus(int n, double major, double minor, double noise, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 2.0 * M_PI), accept(0.0, 1.0);
  PointCloud c;
  while (static_cast<int>(c.size()) < n) {
    const double a = u(rng), b = u(rng);
    // Area element is proportional to (major + minor cos b): rejection sampling.
    if (accept(rng) > (major + minor * std::cos(b)) / (major + minor)) continue;
    const Eigen::Vector3d nrm(std::cos(b) * std::cos(a), std::cos(b) * std::sin(a), std::sin(b));
    const Eigen::Vector3d centre(major * std::cos(a), major * std::sin(a), 0.0);
    add(c, centre + minor * nrm, nrm, noise, rng);
  }
  return c;
}

PointCloud sample_rounded_box(int n, double a, double r, double noise, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-a - 0.0, a);
  std::normal_distribution<double> g;
  PointCloud c;
  // Project random points of the enclosing cube onto the surface: the
  // rounded box is the set at distance r from the inner box [-(a-r), a-r]^3.
  const double inner = a - r;
  while (static_cast<int>(c.size()) < n) {
    const Eigen::Vector3d d = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    const Eigen::Vector3d q(u(rng), u(rng), u(rng));
    const Eigen::Vector3d core = q.cwiseMax(-inner).cwiseMin(inner);
    Eigen::Vector3d off = q - core;
    if (off.norm() < 1e-9) off = d;
    const Eigen::Vector3d nrm = off.normalized();
    // Keep a subset so faces, edges and corners get roughly area-uniform density.
    const int free_axes = int((q.array().abs() > inner).count());
    if (free_axes == 0) continue;
    add(c, core + r * nrm, nrm, noise, rng);
  }
  return c;
}

PointCloud sample_plane_patch(int n, double s, double noise, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-s, s);
  PointCloud c;
  for (int i = 0; i < n; ++i) add(c, Eigen::Vector3d(u(rng), u(rng), 0.0), Eigen::Vector3d::UnitZ(), noise, rng);
  return c;
}

void coarsen_to_axis_directions(PointCloud& points) {
  for (auto& n : points.normals) {
    int axis;
    n.cwiseAbs().maxCoeff(&axis);
    const float sign = n[axis] >= 0 ? 1.0f : -1.0f;
    n.setZero();
    n[axis] = sign;
  }
}

MeshTopology analyze_topology(const TriangleMesh& mesh) {
  MeshTopology t;
  t.vertices = mesh.num_vertices();
  t.faces = mesh.num_faces();
  std::map<std::pair<int, int>, std::pair<int, int>> edges;  // (min,max) -> (count, forward count)
  for (const auto& f : mesh.faces) {
    for (int c = 0; c < 3; ++c) {
      const int a = f[c], b = f[(c + 1) % 3];
      auto& e = edges[{std::min(a, b), std::max(a, b)}];
      ++e.first;
      if (a < b) ++e.second;
    }
  }
  t.edges = edges.size();
  for (const auto& [key, e] : edges) {
    if (e.first == 1) ++t.boundary_edges;
    if (e.first > 2) ++t.nonmanifold_edges;
    if (e.first == 2 && e.second != 1) ++t.misoriented_edges;
  }
  std::vector<int> parent(mesh.num_vertices());
  std::iota(parent.begin(), parent.end(), 0);
  std::function<int(int)> root = [&](int x) { return parent[x] == x ? x : parent[x] = root(parent[x]); };
  for (const auto& f : mesh.faces) {
    parent[root(f[1])] = root(f[0]);
    parent[root(f[2])] = root(f[0]);
  }
  std::set<int> roots;
  for (const auto& f : mesh.faces) roots.insert(root(f[0]));
  t.components = static_cast<int>(roots.size());
  return t;
}

double signed_volume(const TriangleMesh& mesh) {
  double v = 0.0;
  for (const auto& f : mesh.faces) {
    const Eigen::Vector3d a = mesh.vertices[f[0]].cast<double>(), b = mesh.vertices[f[1]].cast<double>(),
                          c = mesh.vertices[f[2]].cast<double>();
    v += a.dot(b.cross(c)) / 6.0;
  }
  return v;
}

}  // namespace hos::recon::testing
