// The vertical estimated from a set of true cameras against the set's own
// vertical: the camera x axes (texture/up_direction.h, "gravity") and the
// mean camera up, as angles in degrees.
//
//   hos-up-bench --strecha DIR/gt_dense_cameras [--up 0,0,-1]
//
// Strecha et al.'s frames have -Z up (docs/pipeline.md, "Up from gravity").
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>

#include "core/error.h"
#include "core/reference_cameras.h"
#include "texture/up_direction.h"

int main(int argc, char** argv) {
  std::string folder;
  std::vector<double> true_up{0.0, 0.0, -1.0};
  CLI::App app{"hos-up-bench: estimated vertical of true cameras against the set's vertical"};
  app.add_option("--strecha", folder, "folder of Strecha .camera files")->required();
  app.add_option("--up", true_up, "the set's up direction X,Y,Z")->delimiter(',')->expected(3);
  CLI11_PARSE(app, argc, argv);
  try {
    std::vector<hos::texture::CameraPose> cameras;
    for (const auto& [name, pose] : hos::read_strecha_cameras(folder)) {
      cameras.push_back({name, pose.cam_from_world, pose.centre});
    }
    const Eigen::Vector3d up = Eigen::Vector3d(true_up[0], true_up[1], true_up[2]).normalized();
    auto angle = [&](const Eigen::Vector3d& v) {
      return std::acos(std::clamp(v.normalized().dot(up), -1.0, 1.0)) * 180.0 / 3.14159265358979323846;
    };
    const hos::texture::UpEstimate estimate = hos::texture::estimate_up(cameras, {});
    const Eigen::Vector3d& e = estimate.x_axis_eigenvalues;
    std::cout << std::fixed << std::setprecision(2) << cameras.size() << " cameras; "
              << "up from " << hos::texture::up_method_name(estimate.method) << ": " << angle(estimate.up)
              << " deg; mean camera up: " << angle(hos::texture::mean_camera_up(cameras))
              << " deg; x-axis eigenvalue ratio " << std::setprecision(4) << e[0] / e[1] << "\n";
  } catch (const hos::Error& e) {
    std::cerr << "hos-up-bench: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
