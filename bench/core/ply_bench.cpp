// PLY load speed (not a test): writes a binary little-endian point cloud with
// positions, normals and colours, then times read_point_cloud_ply on it.
// Usage: hos-ply-bench <points> <file>
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/ply_io.h"

namespace {
// User plus system CPU seconds of this process so far: on a shared machine
// the wall time depends on the load, the CPU time much less.
double cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s <points> <file>\n", argv[0]);
    return 2;
  }
  const std::size_t n = std::stoull(argv[1]);
  const std::filesystem::path path = argv[2];
  hos::PointCloud cloud;
  cloud.positions.resize(n);
  cloud.normals.resize(n);
  cloud.colors.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float t = static_cast<float>(i);
    cloud.positions[i] = Eigen::Vector3f(t, 0.5f * t, -t);
    cloud.normals[i] = Eigen::Vector3f(0, 0, 1);
    cloud.colors[i] = {static_cast<unsigned char>(i), 10, 20};
  }
  hos::write_point_cloud_ply(path, cloud, hos::PlyFormat::kBinaryLittleEndian);
  const double cpu_start = cpu_seconds();
  const auto start = std::chrono::steady_clock::now();
  const hos::PointCloud loaded = hos::read_point_cloud_ply(path);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double cpu = cpu_seconds() - cpu_start;
  std::printf("points %zu  file %.1f MB  read %.3f s wall, %.3f s CPU (all threads)\n", loaded.size(),
              static_cast<double>(std::filesystem::file_size(path)) / 1e6, seconds, cpu);
  return loaded.size() == n ? 0 : 1;
}
