// Plain data types shared by all stages: oriented point sets and triangle meshes.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace hos {

using Rgb8 = std::array<std::uint8_t, 3>;

// An (optionally oriented, coloured, weighted) point set, structure of arrays.
// positions is N; each other array is either empty or N long.
struct PointCloud {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;  // not necessarily unit length
  std::vector<Rgb8> colors;
  std::vector<float> confidence;
  // Further per-point scalar properties read from or written to PLY, by name.
  std::map<std::string, std::vector<float>> scalars;

  std::size_t size() const { return positions.size(); }
  bool empty() const { return positions.empty(); }
  bool has_normals() const { return !normals.empty(); }
  bool has_colors() const { return !colors.empty(); }
  bool has_confidence() const { return !confidence.empty(); }
  // Throws std::logic_error if an attribute array has the wrong length.
  void check_consistent() const;
};

// A triangle mesh with shared vertices. vertices is V; normals and colors are
// empty or V long; faces is F, each (i, j, k) counter-clockwise seen from outside.
struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3f> normals;
  std::vector<Rgb8> colors;
  std::vector<Eigen::Vector3i> faces;
  // Further per-vertex scalar properties (e.g. "quality"), by name.
  std::map<std::string, std::vector<float>> vertex_scalars;

  std::size_t num_vertices() const { return vertices.size(); }
  std::size_t num_faces() const { return faces.size(); }
  // Throws std::logic_error if an attribute array has the wrong length or a
  // face index is out of range.
  void check_consistent() const;
};

// Axis-aligned bounding box.
struct BoundingBox {
  Eigen::Vector3f min = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  Eigen::Vector3f max = Eigen::Vector3f::Constant(std::numeric_limits<float>::lowest());

  void extend(const Eigen::Vector3f& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  bool valid() const { return (max.array() >= min.array()).all(); }
  Eigen::Vector3f extent() const { return max - min; }
  Eigen::Vector3f center() const { return 0.5f * (min + max); }
  float diagonal() const { return extent().norm(); }
};

BoundingBox bounding_box(const std::vector<Eigen::Vector3f>& points);

}  // namespace hos
