// A hos-synth scene written as an undistorted workspace, with its
// ground-truth renderings (depth and normal maps), for the mvs tests.
#pragma once

#include <memory>

#include "core/undistorted_workspace.h"
#include "synth/dataset.h"
#include "tests/support/test_support.h"

namespace hos::mvs_testing {

struct SyntheticWorkspace {
  std::unique_ptr<hos::testing::TempDir> dir;
  UndistortedWorkspace workspace;
  synth::RenderedDataset truth;
  double diagonal = 0.0;  // of the objects' bounding box
};

// 12 views at 320x240 of the default scene (seed 1).
const SyntheticWorkspace& synthetic_workspace();

}  // namespace hos::mvs_testing
