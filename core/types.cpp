#include "core/types.h"

#include <stdexcept>

namespace hos {
namespace {

void check_length(std::size_t expected, std::size_t actual, const char* what) {
  if (actual != 0 && actual != expected) {
    throw std::logic_error(std::string(what) + " has " + std::to_string(actual) + " entries, expected " +
                           std::to_string(expected));
  }
}

}  // namespace

void PointCloud::check_consistent() const {
  check_length(size(), normals.size(), "normals");
  check_length(size(), colors.size(), "colors");
  check_length(size(), confidence.size(), "confidence");
  for (const auto& [name, values] : scalars) check_length(size(), values.size(), name.c_str());
}

void TriangleMesh::check_consistent() const {
  check_length(num_vertices(), normals.size(), "vertex normals");
  check_length(num_vertices(), colors.size(), "vertex colors");
  for (const auto& [name, values] : vertex_scalars) {
    check_length(num_vertices(), values.size(), name.c_str());
  }
  const int n = static_cast<int>(num_vertices());
  for (const auto& f : faces) {
    if ((f.array() < 0).any() || (f.array() >= n).any()) {
      throw std::logic_error("face index out of range");
    }
  }
}

BoundingBox bounding_box(const std::vector<Eigen::Vector3f>& points) {
  BoundingBox box;
  for (const auto& p : points) box.extend(p);
  return box;
}

}  // namespace hos
