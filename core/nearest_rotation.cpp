#include "core/nearest_rotation.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>

namespace hos {

Eigen::Matrix2d nearest_rotation(const Eigen::Matrix2d& c) {
  return Eigen::Rotation2Dd(std::atan2(c(1, 0) - c(0, 1), c(0, 0) + c(1, 1))).toRotationMatrix();
}

// The SVD is fixed-size: a dynamic-size one costs each build about 15 CPU
// seconds of template instantiation.
Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& c) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(c, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d sign = Eigen::Vector3d::Ones();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) sign.z() = -1.0;
  return svd.matrixU() * sign.asDiagonal() * svd.matrixV().transpose();
}

}  // namespace hos
