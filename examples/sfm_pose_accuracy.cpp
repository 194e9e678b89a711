// Compares the cameras of a hos-sfm result with ground-truth cameras after a
// similarity alignment of the camera centres (Umeyama 1991):
//
//   sfm_pose_accuracy WS/sfm/undistorted/sparse strecha  DATA/gt_dense_cameras
//   sfm_pose_accuracy WS/sfm/undistorted/sparse middlebury DATA/templeSR_par.txt
//   sfm_pose_accuracy WS/sfm/undistorted/sparse colmap SCENE/sparse   (e.g. hos-synth's truth)
//
// Ground truth formats: Strecha et al. (one "<image>.camera" file per image:
// K, distortion, camera-to-world R, centre C, size; x ~ K R^T (X - C)) and
// Middlebury multi-view ("name K(9) R(9) t(3)" lines, x ~ K [R | t]).
// Prints per-image errors, the centre RMSE and the median / maximum centre error as a
// percentage of the diagonal of the true camera centres' bounding box, and
// rotation errors in degrees.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include "core/colmap_io.h"
#include "core/error.h"
#include "core/reference_cameras.h"

namespace fs = std::filesystem;

namespace {

using Pose = hos::ReferencePose;

std::map<std::string, Pose> read_colmap_truth(const fs::path& folder) {
  std::map<std::string, Pose> poses;
  for (const auto& [id, image] : hos::read_colmap_model(folder).images) {
    poses[image.name] = {image.rotation(), image.center()};
  }
  return poses;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: sfm_pose_accuracy MODEL_DIR strecha|middlebury|colmap GT_PATH\n";
    return 2;
  }
  try {
    const hos::SparseModel model = hos::read_colmap_model(argv[1]);
    const std::string format = argv[2];
    const auto truth = format == "strecha"  ? hos::read_strecha_cameras(argv[3])
                       : format == "colmap" ? read_colmap_truth(argv[3])
                                            : hos::read_middlebury_cameras(argv[3]);
    std::vector<std::string> names;
    std::vector<Eigen::Vector3d> estimated, expected;
    Eigen::AlignedBox3d box;
    for (const auto& [name, pose] : truth) box.extend(pose.centre);
    for (const auto& [id, image] : model.images) {
      const auto it = truth.find(image.name);
      if (it == truth.end()) continue;
      names.push_back(image.name);
      estimated.push_back(image.center());
      expected.push_back(it->second.centre);
    }
    if (names.size() < 3) {
      std::cerr << "fewer than 3 images in common with the ground truth\n";
      return 4;
    }
    Eigen::Matrix3Xd a(3, names.size()), b(3, names.size());
    for (std::size_t i = 0; i < names.size(); ++i) {
      a.col(i) = estimated[i];
      b.col(i) = expected[i];
    }
    const Eigen::Matrix4d similarity = Eigen::umeyama(a, b, true);
    const double scale = similarity.block<3, 3>(0, 0).col(0).norm();
    const Eigen::Matrix3d rotation = similarity.block<3, 3>(0, 0) / scale;
    const double diagonal = box.diagonal().norm();
    std::vector<double> centre_errors, rotation_errors;
    double squared_sum = 0.0;
    std::cout << std::fixed << std::setprecision(4);
    for (std::size_t i = 0; i < names.size(); ++i) {
      const auto& image = *model.find_image(names[i]);
      const Eigen::Vector3d aligned = (similarity * estimated[i].homogeneous()).head<3>();
      const double centre_error = (aligned - expected[i]).norm() / diagonal * 100.0;
      const Eigen::Matrix3d delta =
          truth.at(names[i]).cam_from_world.transpose() * image.rotation() * rotation.transpose();
      const double angle = std::acos(std::clamp((delta.trace() - 1.0) / 2.0, -1.0, 1.0)) * 180.0 / M_PI;
      centre_errors.push_back(centre_error);
      squared_sum += centre_error * centre_error;
      rotation_errors.push_back(angle);
      std::cout << names[i] << "  centre " << centre_error << " %  rotation " << angle << " deg\n";
    }
    std::cout << "images compared: " << names.size() << " of " << truth.size() << " with ground truth\n"
              << "centre RMSE (% of camera bbox diagonal): " << std::sqrt(squared_sum / names.size()) << "\n"
              << "centre error (% of camera bbox diagonal): median " << median(centre_errors) << ", max "
              << *std::max_element(centre_errors.begin(), centre_errors.end()) << "\n"
              << "rotation error (deg): median " << median(rotation_errors) << ", max "
              << *std::max_element(rotation_errors.begin(), rotation_errors.end()) << "\n";
  } catch (const std::exception& e) {
    std::cerr << "sfm_pose_accuracy: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
