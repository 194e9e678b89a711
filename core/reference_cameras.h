// Ground-truth camera poses published with public multi-view datasets, for
// comparing hos-sfm's cameras with them (examples/sfm_pose_accuracy,
// bench/mvs/box_check):
//  - Strecha et al. (EPFL): one "<image>.camera" file per image with K (9),
//    distortion (3), camera-to-world R (9), centre C (3) and the image size;
//  - Middlebury multi-view "_par.txt": a count, then "name K(9) R(9) t(3)"
//    lines with x ~ K [R | t].
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <string>

namespace hos {

struct ReferencePose {
  Eigen::Matrix3d cam_from_world = Eigen::Matrix3d::Identity();
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // in world coordinates
};

// Image name -> pose. Throw InputError naming the file and the reason.
std::map<std::string, ReferencePose> read_strecha_cameras(const std::filesystem::path& folder);
std::map<std::string, ReferencePose> read_middlebury_cameras(const std::filesystem::path& par_file);

}  // namespace hos
