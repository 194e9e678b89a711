// A hos-synth scene written as an undistorted workspace, with its
// ground-truth renderings (depth and normal maps), for the mvs tests.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>

#include "core/undistorted_workspace.h"
#include "synth/dataset.h"
#include "synth/scene.h"
#include "tests/support/test_support.h"

namespace hos::mvs_testing {

struct SyntheticWorkspace {
  std::unique_ptr<hos::testing::TempDir> dir;
  UndistortedWorkspace workspace;
  synth::RenderedDataset truth;
  synth::Scene scene;
  double diagonal = 0.0;  // of the objects' bounding box
};

SyntheticWorkspace make_synthetic_workspace(const synth::SceneOptions& scene_options,
                                            const synth::DatasetOptions& options);

// The scene's workspace copied into dir with every image passed through
// edit (image, index in image id order), then loaded.
UndistortedWorkspace edited_copy(const SyntheticWorkspace& s,
                                 const hos::testing::TempDir& dir,
                                 const std::function<void(cv::Mat&, std::size_t)>& edit);

// 12 views at 320x240 of the default scene (seed 1).
const SyntheticWorkspace& synthetic_workspace();

// Where a point lies relative to the true surface in the view that sees it
// best: the distance along that view's ray to the rendered surface (an upper
// bound of the distance to the surface), and the true normal there.
struct TruthAtPoint {
  double distance = 1e30;
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
};
TruthAtPoint truth_at(const SyntheticWorkspace& s, const Eigen::Vector3d& x);

// The true surface point pixel (x, y) of view v (in image id order) sees;
// nothing where the view sees no surface.
std::optional<Eigen::Vector3d> surface_point(const SyntheticWorkspace& s, std::size_t v, int x, int y);

}  // namespace hos::mvs_testing
