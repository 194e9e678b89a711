// Similarity alignment of a recovered reconstruction to ground truth: the
// Umeyama fit between camera centres matched by image name, and the pose
// errors that remain after it.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/sparse_model.h"
#include "core/types.h"

namespace hos::eval {

// x' = scale * R * x + t.
struct Similarity3 {
  double scale = 1.0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();

  Eigen::Vector3d apply(const Eigen::Vector3d& x) const { return scale * (R * x) + t; }
  Eigen::Matrix4d matrix() const;
  Similarity3 inverse() const;
};

// Least-squares similarity with dst[i] ~ apply(src[i]) (Umeyama 1991, Eq. 40-42).
// Throws NumericalError for fewer than 3 pairs, mismatched sizes or points
// that are (numerically) all the same.
Similarity3 umeyama(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst);

struct ModelAlignment {
  Similarity3 truth_from_recovered;
  std::vector<std::string> names;  // matched images, sorted by name
  std::vector<double> residuals;   // |aligned recovered centre - true centre| per name
  double rms_residual = 0.0;
};

// Aligns recovered camera centres onto the truth's, matching images by name.
// Throws InputError-free NumericalError when fewer than 3 names match.
ModelAlignment align_models_by_image_name(const SparseModel& recovered, const SparseModel& truth);

struct CameraPoseError {
  std::string name;
  double center_error = 0.0;        // after alignment, as a fraction of scene_size
  double rotation_error_deg = 0.0;  // angle of R_true * R_aligned^T
};

struct CameraPoseComparison {
  Similarity3 truth_from_recovered;
  double scene_size = 0.0;  // bounding-box diagonal of the true camera centres
  int num_recovered = 0;
  int num_truth = 0;
  std::vector<CameraPoseError> cameras;  // matched images, sorted by name
  double mean_center_error = 0.0, median_center_error = 0.0, max_center_error = 0.0;
  double mean_rotation_error_deg = 0.0, median_rotation_error_deg = 0.0, max_rotation_error_deg = 0.0;
};

CameraPoseComparison compare_camera_poses(const SparseModel& recovered, const SparseModel& truth);

// Applies s to every vertex (and rotates normals).
void transform_mesh(TriangleMesh& mesh, const Similarity3& s);
void transform_points(PointCloud& cloud, const Similarity3& s);

}  // namespace hos::eval
