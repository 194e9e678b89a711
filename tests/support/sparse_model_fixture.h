// A small COLMAP model with every kind of field set (two cameras, one of
// them distorted, two images with keypoints, one point with a track), for
// the COLMAP reader tests and fuzzing.
#pragma once

#include "core/sparse_model.h"

namespace hos::testing {

SparseModel small_sparse_model();

}  // namespace hos::testing
