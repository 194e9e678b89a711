#include "eval/render_compare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "core/error.h"
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

// Photos of the unit sphere; run "whole" re-renders it exactly, run "small"
// is a sphere of radius 0.6 in another colour: it covers a part of the
// photo, and only there are the two runs compared.
TEST(RenderCompare, RunsAreComparedOnThePixelsEveryRunCovers) {
  hos::testing::TempDir dir;
  const SparseModel model = two_views();
  render::RenderObject whole{synth::icosphere(3, 1.0), {}};
  whole.material.constant_albedo = Eigen::Vector3f(0.6f, 0.3f, 0.2f);
  render::RenderObject small{synth::icosphere(3, 0.6), {}};
  small.material.constant_albedo = Eigen::Vector3f(0.3f, 0.3f, 0.2f);
  render::RenderOptions options;
  options.lighting.unlit = true;
  std::map<std::string, cv::Mat> small_masks;
  for (const auto& [id, image] : model.images) {
    cv::imwrite((dir.path() / image.name).string(),
                render::render_view({whole}, model.camera_of(image), image, options).color);
    small_masks[image.name] = render::render_view({small}, model.camera_of(image), image, options).mask;
  }
  compare_renders(whole, model, dir.path(), null_reporter(), dir / "whole");
  compare_renders(small, model, dir.path(), null_reporter(), dir / "small");

  const std::filesystem::path whole_view = dir / "whole" / "view0.png", small_view = dir / "small" / "view0.png";
  const SavedRender saved = read_saved_render(small_view);  // the mask survives the PNG
  EXPECT_EQ(cv::norm(saved.mask, small_masks["view0.png"], cv::NORM_INF), 0.0);

  const CommonComparison c = compare_on_common_pixels({whole_view, small_view});
  ASSERT_EQ(c.psnr.size(), 2u);
  EXPECT_EQ(c.photo_pixels, 96u * 72u);
  EXPECT_GT(c.covered_pixels[0], c.covered_pixels[1] + 100);
  EXPECT_EQ(c.common_pixels, c.covered_pixels[1]);  // the small sphere lies inside the whole one
  EXPECT_TRUE(std::isinf(c.psnr[0]));
  EXPECT_LT(c.psnr[1], 30.0);
  // The least-squares gain and offset include the identity: matching never
  // scores worse (beyond 8-bit rounding).
  ASSERT_EQ(c.psnr_exposure_matched.size(), 2u);
  EXPECT_GT(c.psnr_exposure_matched[0], 50.0);
  EXPECT_GE(c.psnr_exposure_matched[1], c.psnr[1] - 0.05);

  // A view of another photo is refused, naming the file.
  try {
    compare_on_common_pixels({whole_view, dir / "small" / "view1.png"});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("view1.png"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_saved_render(dir.path() / "view0.png"), InputError);  // a photo, not a saved view
}

// Writes a view as compare_renders saves it: the render (alpha = mask)
// beside the photo.
void write_saved(const std::filesystem::path& path, const cv::Mat& render, const cv::Mat& mask, const cv::Mat& photo) {
  cv::Mat render_with_mask, photo_opaque, side_by_side;
  cv::cvtColor(render, render_with_mask, cv::COLOR_BGR2BGRA);
  cv::insertChannel(mask, render_with_mask, 3);
  cv::cvtColor(photo, photo_opaque, cv::COLOR_BGR2BGRA);
  cv::hconcat(render_with_mask, photo_opaque, side_by_side);
  ASSERT_TRUE(cv::imwrite(path.string(), side_by_side));
}

// Two runs of a grey 64x48 photo, saved as dir/a.png and dir/b.png. Run
// "a" is off by 30 in a 10x10 block at (50, 20) and by 10 in a 4x4 block at
// (2, 2); run "b" is exact but does not cover the bottom 16 rows nor the
// 2x2 pixels at (0, 0). a's squared error: 90000 + 1600 (per channel).
void write_two_runs(const std::filesystem::path& dir) {
  const cv::Mat photo(48, 64, CV_8UC3, cv::Scalar(100, 100, 100));
  cv::Mat a = photo.clone();
  a(cv::Rect(50, 20, 10, 10)).setTo(cv::Scalar(130, 130, 130));
  a(cv::Rect(2, 2, 4, 4)).setTo(cv::Scalar(110, 110, 110));
  const cv::Mat all(48, 64, CV_8U, cv::Scalar(255));
  cv::Mat part = all.clone();
  part(cv::Rect(0, 32, 64, 16)).setTo(0);
  part(cv::Rect(0, 0, 2, 2)).setTo(0);
  write_saved(dir / "a.png", a, all, photo);
  write_saved(dir / "b.png", photo, part, photo);
}

// The runs of write_two_runs cut into 16-pixel tiles. The tiles carrying
// a's error, largest first, and their figures by hand: (48, 16): 100 pixels
// off by 30 of 256 common, MSE 900 * 100 / 256, share 90000 / (90000 +
// 1600); (0, 0): 16 pixels off by 10 of 252 common, MSE 100 * 16 / 252.
TEST(RenderCompare, WorstTilesAreWhereTheFirstRunsErrorLies) {
  hos::testing::TempDir dir;
  write_two_runs(dir.path());

  CommonOptions options;
  options.tile_size = 16;
  options.worst_tiles = 3;
  options.crops_dir = dir / "crops";
  const CommonComparison c = compare_on_common_pixels({dir / "a.png", dir / "b.png"}, options);
  EXPECT_EQ(c.common_pixels, 64u * 32u - 4u);
  ASSERT_EQ(c.worst_tiles.size(), 3u);  // the third carries no error
  const ErrorRegion& first = c.worst_tiles[0];
  EXPECT_EQ(first.rect.x, 48);
  EXPECT_EQ(first.rect.y, 16);
  EXPECT_EQ(first.rect.width, 16);
  EXPECT_EQ(first.common_pixels, 256u);
  ASSERT_EQ(first.mse.size(), 2u);
  EXPECT_NEAR(first.mse[0], 900.0 * 100 / 256, 1e-9);
  EXPECT_EQ(first.mse[1], 0.0);
  EXPECT_NEAR(first.share, 90000.0 / 91600.0, 1e-12);
  EXPECT_EQ(c.worst_tiles[1].rect.x, 0);
  EXPECT_EQ(c.worst_tiles[1].rect.y, 0);
  EXPECT_EQ(c.worst_tiles[1].common_pixels, 252u);
  EXPECT_NEAR(c.worst_tiles[1].mse[0], 100.0 * 16 / 252, 1e-9);
  EXPECT_EQ(c.worst_tiles[2].share, 0.0);
  // Without worst_tiles none are listed.
  EXPECT_TRUE(compare_on_common_pixels({dir / "a.png", dir / "b.png"}).worst_tiles.empty());

  // The crops of the listed tiles: the photo, then each run; where b does
  // not cover, magenta.
  const cv::Mat crop = cv::imread((dir / "crops" / "tile_48_16.png").string());
  ASSERT_EQ(crop.cols, 48);
  ASSERT_EQ(crop.rows, 16);
  EXPECT_EQ(crop.at<cv::Vec3b>(8, 8), cv::Vec3b(100, 100, 100));       // photo at (56, 24)
  EXPECT_EQ(crop.at<cv::Vec3b>(8, 16 + 8), cv::Vec3b(130, 130, 130));  // a, off there
  EXPECT_EQ(crop.at<cv::Vec3b>(8, 32 + 8), cv::Vec3b(100, 100, 100));  // b
  const cv::Mat corner = cv::imread((dir / "crops" / "tile_0_0.png").string());
  ASSERT_FALSE(corner.empty());
  EXPECT_EQ(corner.at<cv::Vec3b>(0, 32), cv::Vec3b(255, 0, 255));  // b does not cover (0, 0)
  EXPECT_EQ(corner.at<cv::Vec3b>(3, 16 + 3), cv::Vec3b(110, 110, 110));

  // A crops folder that cannot be made is an OutputError naming it.
  options.crops_dir = dir / "a.png" / "crops";
  try {
    compare_on_common_pixels({dir / "a.png", dir / "b.png"}, options);
    FAIL() << "expected OutputError";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("crops"), std::string::npos) << e.what();
  }
  // Crops with neither tiles nor regions to write are refused.
  options.worst_tiles = 0;
  options.crops_dir = dir / "crops";
  EXPECT_THROW(compare_on_common_pixels({dir / "a.png", dir / "b.png"}, options), ConfigError);
}

// Regions given by the caller, on the runs of write_two_runs: (48, 16,
// 16, 8) holds 4 rows of a's 10-pixel-wide error block, 40 pixels off by 30
// of 128 common (MSE 900 * 40 / 128, share 36000 / 91600); (0, 32, 8, 8)
// lies where b covers nothing.
TEST(RenderCompare, RegionsAreMeasuredAndCroppedAsGiven) {
  hos::testing::TempDir dir;
  write_two_runs(dir.path());

  CommonOptions options;
  options.regions = {{48, 16, 16, 8}, {0, 32, 8, 8}};
  options.crops_dir = dir / "crops";
  const CommonComparison c = compare_on_common_pixels({dir / "a.png", dir / "b.png"}, options);
  EXPECT_TRUE(c.worst_tiles.empty());
  ASSERT_EQ(c.regions.size(), 2u);
  EXPECT_EQ(c.regions[0].common_pixels, 128u);
  ASSERT_EQ(c.regions[0].mse.size(), 2u);
  EXPECT_NEAR(c.regions[0].mse[0], 900.0 * 40 / 128, 1e-9);
  EXPECT_EQ(c.regions[0].mse[1], 0.0);
  EXPECT_NEAR(c.regions[0].share, 36000.0 / 91600.0, 1e-12);
  EXPECT_EQ(c.regions[1].common_pixels, 0u);
  EXPECT_TRUE(c.regions[1].mse.empty());
  EXPECT_EQ(c.regions[1].share, 0.0);

  const cv::Mat crop = cv::imread((dir / "crops" / "region_48_16_16x8.png").string());
  ASSERT_EQ(crop.cols, 48);
  ASSERT_EQ(crop.rows, 8);
  EXPECT_EQ(crop.at<cv::Vec3b>(6, 16 + 4), cv::Vec3b(130, 130, 130));  // a at (52, 22)
  EXPECT_EQ(crop.at<cv::Vec3b>(2, 16 + 4), cv::Vec3b(100, 100, 100));  // a at (52, 18), above the block
  const cv::Mat uncovered = cv::imread((dir / "crops" / "region_0_32_8x8.png").string());
  ASSERT_FALSE(uncovered.empty());
  EXPECT_EQ(uncovered.at<cv::Vec3b>(4, 16 + 4), cv::Vec3b(255, 0, 255));  // b covers nothing there

  // A region reaching outside the photo is a ConfigError naming it.
  options.regions = {{60, 40, 8, 16}};
  try {
    compare_on_common_pixels({dir / "a.png", dir / "b.png"}, options);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("60,40,8,16"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hos::eval
