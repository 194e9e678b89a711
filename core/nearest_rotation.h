// The rotation nearest to a matrix: the R maximising trace(R^T C), which is
// the rotation of Umeyama's least-squares similarity between two point sets
// when C is their cross-covariance (Umeyama 1991, Eqs. 39-40). Used by the
// evaluation's model alignment and the GPS placement.
#pragma once

#include <Eigen/Core>

namespace hos {

// In closed form: the rotation by atan2(C10 - C01, C00 + C11).
Eigen::Matrix2d nearest_rotation(const Eigen::Matrix2d& c);

// U diag(1, 1, det(U) det(V)) V^T of C's SVD: a reflection becomes the
// nearest proper rotation.
Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& c);

}  // namespace hos
