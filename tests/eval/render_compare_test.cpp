#include "eval/render_compare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "synth/shapes.h"
#include "tests/eval/test_meshes.h"
#include "tests/support/test_support.h"

namespace hos::eval {
namespace {

// Two cameras looking at a sphere; the photos are the unlit renders of the
// object itself, so re-rendering reproduces them exactly.
SparseModel two_views() {
  SparseModel model;
  model.cameras[1] = Camera::pinhole(1, 96, 72, 80, 80, 48, 36);
  for (int i = 0; i < 2; ++i) {
    ImageRecord image;
    image.id = i + 1;
    image.camera_id = 1;
    image.name = "view" + std::to_string(i) + ".png";
    image.cam_from_world_translation = Eigen::Vector3d(0.1 * i, 0, 4);
    model.images[image.id] = image;
  }
  return model;
}

TEST(RenderCompare, SelfRendersMatchAndAChangedColourDoesNot) {
  hos::testing::TempDir dir;
  render::RenderObject object{synth::icosphere(3, 1.0), {}};
  object.material.constant_albedo = Eigen::Vector3f(0.6f, 0.3f, 0.2f);
  const SparseModel model = two_views();
  render::RenderOptions options;
  options.lighting.unlit = true;
  for (const auto& [id, image] : model.images) {
    const render::RenderedView v = render::render_view({object}, model.camera_of(image), image, options);
    ASSERT_GT(cv::countNonZero(v.mask), 100);
    cv::imwrite((dir.path() / image.name).string(), v.color);
  }
  const RenderComparison same = compare_renders(object, model, dir.path(), null_reporter());
  ASSERT_EQ(same.views.size(), 2u);
  EXPECT_TRUE(std::isinf(same.mean_psnr));
  EXPECT_NEAR(same.mean_ssim, 1.0, 1e-9);

  object.material.constant_albedo = Eigen::Vector3f(0.3f, 0.3f, 0.2f);
  const RenderComparison other = compare_renders(object, model, dir.path(), null_reporter(), dir / "saved");
  // The saved image is the render beside the photo.
  for (const auto& [id, image] : model.images) {
    const cv::Mat saved =
        cv::imread((dir / "saved" / (std::filesystem::path(image.name).stem().string() + ".png")).string());
    ASSERT_FALSE(saved.empty()) << image.name;
    EXPECT_EQ(saved.cols, 2 * model.camera_of(image).width);
    EXPECT_EQ(saved.rows, model.camera_of(image).height);
  }
  EXPECT_TRUE(std::isfinite(other.mean_psnr));
  EXPECT_LT(other.mean_psnr, 30.0);
  EXPECT_LT(other.mean_ssim, 1.0);
}

}  // namespace
}  // namespace hos::eval
