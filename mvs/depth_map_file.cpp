#include "mvs/depth_map_file.h"

#include <algorithm>
#include <cstdint>
#include <fstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "mvs/raw_mat_io.h"

namespace hos::mvs {
namespace {

constexpr char kDepthMapTag[8] = {'H', 'O', 'S', 'D', 'M', 'A', 'P', '1'};

}  // namespace

std::filesystem::path depth_map_file(const std::filesystem::path& folder, const std::string& name) {
  return folder / (name + ".dmap");
}

void write_depth_map_file(const std::filesystem::path& file, const DepthMap& map) {
  std::filesystem::create_directories(file.parent_path());
  write_atomically(file, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    const std::int32_t size[2] = {map.depth.cols, map.depth.rows};
    out.write(kDepthMapTag, sizeof(kDepthMapTag));
    out.write(reinterpret_cast<const char*>(size), sizeof(size));
    for (const cv::Mat* m : {&map.depth, &map.normal, &map.cost}) write_raw_mat(out, *m);
    if (!out) throw OutputError(file.string(), "the depth map");
  });
}

DepthMap read_depth_map_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), "missing depth map; compute it with hos-mvs --views first");
  char tag[sizeof(kDepthMapTag)] = {};
  std::int32_t size[2] = {0, 0};
  in.read(tag, sizeof(tag));
  in.read(reinterpret_cast<char*>(size), sizeof(size));
  if (!in || !std::equal(tag, tag + sizeof(tag), kDepthMapTag)) throw InputError(file.string(), "not a depth map");
  // The size must account for the file's length before anything is
  // allocated: a damaged size would otherwise ask for gigabytes.
  const std::uintmax_t pixels = size[0] > 0 && size[1] > 0 ? std::uintmax_t(size[0]) * std::uintmax_t(size[1]) : 0;
  const std::uintmax_t floats_per_pixel = 5;  // depth, normal (3), cost
  if (pixels == 0 || std::filesystem::file_size(file) !=
                         sizeof(kDepthMapTag) + sizeof(size) + pixels * floats_per_pixel * sizeof(float)) {
    throw InputError(file.string(), "truncated or damaged depth map");
  }
  const int width = size[0], height = size[1];
  DepthMap map{cv::Mat(height, width, CV_32F), cv::Mat(height, width, CV_32FC3), cv::Mat(height, width, CV_32F)};
  for (cv::Mat* m : {&map.depth, &map.normal, &map.cost}) read_raw_mat(in, *m);
  if (!in) throw InputError(file.string(), "truncated or damaged depth map");
  return map;
}

}  // namespace hos::mvs
