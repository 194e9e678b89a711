// core/undistorted_workspace.*: a complete workspace loads; a missing image
// file and a distorted camera are rejected with InputError naming the cause.
#include "core/undistorted_workspace.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/colmap_io.h"
#include "core/error.h"
#include "tests/support/test_support.h"

namespace hos {
namespace {

namespace fs = std::filesystem;

SparseModel two_view_model() {
  SparseModel m;
  m.cameras[1] = Camera::pinhole(1, 64, 48, 50, 50, 32, 24);
  for (int id : {1, 2}) {
    ImageRecord im;
    im.id = id;
    im.camera_id = 1;
    im.name = "view_" + std::to_string(id) + ".png";
    im.cam_from_world_translation = Eigen::Vector3d(0.1 * id, 0, 3);
    m.images[id] = im;
  }
  return m;
}

// Writes the model and empty files standing in for the photos, except `skip`.
void make_workspace(const fs::path& root, const SparseModel& model, const std::string& skip = {}) {
  fs::create_directories(root / "images");
  write_colmap_model(model, root / "sparse", ColmapFormat::kBinary);
  for (const auto& [id, im] : model.images) {
    if (im.name != skip) std::ofstream(root / "images" / im.name) << "x";
  }
}

TEST(UndistortedWorkspace, LoadsCompleteWorkspace) {
  hos::testing::TempDir dir;
  const SparseModel model = two_view_model();
  make_workspace(dir.path(), model);
  const UndistortedWorkspace ws = load_undistorted_workspace(dir.path());
  EXPECT_EQ(ws.model.images.size(), 2u);
  EXPECT_EQ(ws.image_path(ws.model.images.at(2)), dir.path() / "images" / "view_2.png");
}

TEST(UndistortedWorkspace, MissingImageNamesTheFile) {
  hos::testing::TempDir dir;
  make_workspace(dir.path(), two_view_model(), "view_2.png");
  try {
    load_undistorted_workspace(dir.path());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(e.path().find("view_2.png"), std::string::npos) << e.what();
  }
}

TEST(UndistortedWorkspace, DistortedCameraRejected) {
  hos::testing::TempDir dir;
  SparseModel model = two_view_model();
  Camera& cam = model.cameras.at(1);
  cam.model = CameraModel::kSimpleRadial;
  cam.params = {50, 32, 24, 0.05};
  make_workspace(dir.path(), model);
  try {
    load_undistorted_workspace(dir.path());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("SIMPLE_RADIAL"), std::string::npos) << e.what();
  }
}

TEST(UndistortedWorkspace, MissingModelIsInputError) {
  hos::testing::TempDir dir;
  fs::create_directories(dir.path() / "images");
  EXPECT_THROW(load_undistorted_workspace(dir.path()), InputError);
}

}  // namespace
}  // namespace hos
