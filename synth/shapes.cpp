#include "synth/shapes.h"

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <random>

namespace hos::synth {

TriangleMesh grid_mesh(int n, float spacing, const std::function<float(float, float)>& height) {
  TriangleMesh mesh;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const float x = static_cast<float>(i) * spacing, y = static_cast<float>(j) * spacing;
      mesh.vertices.emplace_back(x, y, height ? height(x, y) : 0.0f);
    }
  }
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      mesh.faces.emplace_back(a, b, d);
      mesh.faces.emplace_back(a, d, c);
    }
  }
  return mesh;
}

TriangleMesh icosphere(int subdivisions, float radius, const Eigen::Vector3f& centre) {
  TriangleMesh m;
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  m.vertices = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (auto& v : m.vertices) v.normalize();
  m.faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
             {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
             {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.vertices.push_back((m.vertices[a] + m.vertices[b]).normalized());
      const int id = static_cast<int>(m.vertices.size()) - 1;
      mid.emplace(key, id);
      return id;
    };
    std::vector<Eigen::Vector3i> faces;
    faces.reserve(4 * m.faces.size());
    for (const Eigen::Vector3i& f : m.faces) {
      const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      faces.emplace_back(f[0], ab, ca);
      faces.emplace_back(f[1], bc, ab);
      faces.emplace_back(f[2], ca, bc);
      faces.emplace_back(ab, bc, ca);
    }
    m.faces = std::move(faces);
  }
  if (radius != 1.0f || !centre.isZero()) {
    for (Eigen::Vector3f& v : m.vertices) v = radius * v + centre;
  }
  return m;
}

namespace {

void add(PointCloud& c, const Eigen::Vector3d& p, const Eigen::Vector3d& n, double noise, std::mt19937& rng) {
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

}  // namespace hos::synth
