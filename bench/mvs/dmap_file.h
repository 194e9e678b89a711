// hos-mvs's .dmap files (mvs/run_mvs.cpp writes them: a tag, width and
// height, then the depth, normal and cost rows as raw floats), read by the
// bench programs without linking hos_mvs.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/error.h"

namespace hos::bench {

// The cost mvs/patch_match.cpp gives a pixel too flat to be scored.
constexpr float kTexturelessCost = 3.0f;

struct DepthMapFile {
  int width = 0, height = 0;
  std::vector<float> depth, cost;  // row-major; depth 0 where there is none
};

inline DepthMapFile read_dmap(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file, "missing depth map");
  char tag[8] = {};
  std::int32_t size[2] = {0, 0};
  in.read(tag, sizeof(tag));
  in.read(reinterpret_cast<char*>(size), sizeof(size));
  if (!in || std::memcmp(tag, "HOSDMAP1", sizeof(tag)) != 0 || size[0] <= 0 || size[1] <= 0) {
    throw InputError(file, "not a depth map");
  }
  const std::size_t n = static_cast<std::size_t>(size[0]) * static_cast<std::size_t>(size[1]);
  DepthMapFile map{size[0], size[1], std::vector<float>(n), std::vector<float>(n)};
  std::vector<float> normal(3 * n);
  for (std::vector<float>* v : {&map.depth, &normal, &map.cost}) {
    in.read(reinterpret_cast<char*>(v->data()), static_cast<std::streamsize>(v->size() * sizeof(float)));
  }
  if (!in) throw InputError(file, "truncated depth map");
  return map;
}

// The camera's calibration at the depth map's size (hos-mvs matches at a
// scaled size; pixel (x, y)'s centre is at (x + 0.5, y + 0.5)).
inline Eigen::Matrix3d depth_map_calibration(const Camera& camera, const DepthMapFile& map) {
  Eigen::Matrix3d K = camera.calibration_matrix();
  K.row(0) *= static_cast<double>(map.width) / camera.width;
  K.row(1) *= static_cast<double>(map.height) / camera.height;
  return K;
}

}  // namespace hos::bench
