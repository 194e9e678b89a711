// Masks of the photos (sfm/photo_masks.h): found by COLMAP's naming, staged
// with the photo's EXIF turn and downscale, refused with the file and the
// reason, and undistorted as the photos are.
#include "sfm/photo_masks.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "core/error.h"
#include "core/image_mask.h"
#include "sfm/colmap_steps.h"
#include "sfm/image_inputs.h"
#include "tests/sfm/jpeg_fixtures.h"
#include "tests/support/message_log.h"
#include "tests/support/test_support.h"

namespace hos::sfm {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

using testing::write_bytes;

// A mask of width x height, black (masked) in the top-left quadrant only.
cv::Mat top_left_masked(int width, int height) {
  cv::Mat mask(height, width, CV_8U, cv::Scalar(255));
  mask(cv::Rect(0, 0, width / 2, height / 2)).setTo(0);
  return mask;
}

void write_photos(const fs::path& folder, int count, int width, int height) {
  fs::create_directories(folder);
  for (int i = 0; i < count; ++i) {
    cv::imwrite((folder / cv::format("p%d.jpg", i)).string(), testing::gradient_image(width, height));
  }
}

cv::Mat read_grey(const fs::path& file) { return cv::imread(file.string(), cv::IMREAD_GRAYSCALE); }

TEST(PhotoMasks, MaskFollowsTheExifTurnAndTheDownscaleOfItsPhoto) {
  hos::testing::TempDir dir;
  const fs::path photos = dir / "photos";
  write_photos(photos / "sub", 2, 160, 120);
  // Stored 160x120 sideways, to be turned clockwise (orientation 6) and
  // downscaled to 80 px: staged 60x80.
  testing::PhoneExif exif;
  exif.orientation = 6;
  write_bytes(photos / "sub" / "turned.jpg", testing::jpeg_with_phone_exif(testing::gradient_image(160, 120), exif));
  const fs::path masks = dir / "masks";
  fs::create_directories(masks / "sub");
  cv::imwrite((masks / "sub" / "turned.jpg.png").string(), top_left_masked(160, 120));
  cv::imwrite((masks / "sub" / "p0.jpg.png").string(), top_left_masked(160, 120));
  SfmOptions options;
  options.masks = masks.string();
  options.max_image_size = 80;
  hos::testing::MessageLog log;
  const ImageInputs inputs = prepare_images(photos, dir / "ws" / "images", options, log);
  ASSERT_EQ(inputs.images.size(), 3u);
  EXPECT_EQ(inputs.masked_photos(), 2);
  EXPECT_EQ(inputs.mask_folder, dir / "ws" / "masks");
  EXPECT_THAT(log.all(), HasSubstr("masks: 2 of 3 photos have a mask"));

  // Turned clockwise, the stored top-left corner becomes the top-right one.
  const cv::Mat turned = read_grey(dir / "ws" / "masks" / "sub" / "turned.jpg.png");
  ASSERT_EQ(turned.cols, 60);
  ASSERT_EQ(turned.rows, 80);
  EXPECT_EQ(turned.at<unsigned char>(5, 55), kMaskedOut);      // top right
  EXPECT_EQ(turned.at<unsigned char>(5, 5), kUsable);          // top left
  EXPECT_EQ(turned.at<unsigned char>(75, 55), kUsable);        // bottom right
  EXPECT_EQ(cv::countNonZero(turned == kMaskedOut), 30 * 40);  // a quarter, no blending
  const cv::Mat plain = read_grey(dir / "ws" / "masks" / "sub" / "p0.jpg.png");
  ASSERT_EQ(plain.cols, 80);
  ASSERT_EQ(plain.rows, 60);
  EXPECT_EQ(plain.at<unsigned char>(5, 5), kMaskedOut);
  EXPECT_EQ(cv::countNonZero(plain == kMaskedOut), 40 * 30);
  // The photo without a mask is used whole.
  EXPECT_FALSE(fs::exists(dir / "ws" / "masks" / "sub" / "p1.jpg.png"));
  for (const StagedImage& image : inputs.images) EXPECT_EQ(image.masked, image.name != "sub/p1.jpg") << image.name;
}

TEST(PhotoMasks, UprightMaskOfATurnedPhotoIsTakenAsDrawnUpright) {
  hos::testing::TempDir dir;
  const fs::path photos = dir / "photos";
  write_photos(photos, 2, 160, 120);
  testing::PhoneExif exif;
  exif.orientation = 6;
  write_bytes(photos / "turned.jpg", testing::jpeg_with_phone_exif(testing::gradient_image(160, 120), exif));
  // Beside the photo, drawn over the upright 120x160 picture.
  cv::imwrite((photos / "turned.jpg.png").string(), top_left_masked(120, 160));
  const ImageInputs inputs = prepare_images(photos, dir / "ws" / "images", SfmOptions{}, null_reporter());
  ASSERT_EQ(inputs.images.size(), 3u) << "the mask beside a photo is not a photo";
  const cv::Mat staged = read_grey(dir / "ws" / "masks" / "turned.jpg.png");
  ASSERT_EQ(staged.size(), cv::Size(120, 160));
  EXPECT_EQ(staged.at<unsigned char>(5, 5), kMaskedOut);
  EXPECT_EQ(staged.at<unsigned char>(5, 115), kUsable);
}

// A renderer's RGBA photos: the transparent pixels (alpha below half) are
// masked, the staged copy has no alpha channel, an opaque RGBA photo gets no
// mask, and a mask file beside a photo wins over its alpha.
TEST(PhotoMasks, AlphaChannelMasksTheTransparentPixels) {
  hos::testing::TempDir dir;
  const fs::path photos = dir / "photos";
  write_photos(photos, 2, 160, 120);
  const auto rgba = [](const cv::Mat& alpha) {
    std::vector<cv::Mat> channels;
    cv::split(testing::gradient_image(alpha.cols, alpha.rows), channels);
    channels.push_back(alpha);
    cv::Mat out;
    cv::merge(channels, out);
    return out;
  };
  cv::Mat alpha(120, 160, CV_8U, cv::Scalar(255));
  alpha(cv::Rect(0, 0, 80, 60)).setTo(127);   // just under half opaque
  alpha(cv::Rect(80, 0, 80, 60)).setTo(128);  // half opaque: kept
  cv::imwrite((photos / "cut.png").string(), rgba(alpha));
  cv::Mat opaque16;
  rgba(cv::Mat(120, 160, CV_8U, cv::Scalar(255))).convertTo(opaque16, CV_16U, 257.0);
  cv::imwrite((photos / "opaque.png").string(), opaque16);
  cv::imwrite((photos / "own.png").string(), rgba(cv::Mat(120, 160, CV_8U, cv::Scalar(0))));
  cv::imwrite((photos / "own.png.png").string(), top_left_masked(160, 120));
  hos::testing::MessageLog log;
  const ImageInputs inputs = prepare_images(photos, dir / "ws" / "images", SfmOptions{}, log);
  ASSERT_EQ(inputs.images.size(), 5u);
  EXPECT_EQ(inputs.masked_photos(), 2);
  EXPECT_THAT(log.all(), HasSubstr("masks: 1 of 5 photos are transparent in places"));
  EXPECT_THAT(log.all(), HasSubstr("masks: 1 of 5 photos have a mask (PHOTO.png beside PHOTO)"));

  const cv::Mat cut = read_grey(dir / "ws" / "masks" / "cut.png.png");
  ASSERT_EQ(cut.size(), cv::Size(160, 120));
  EXPECT_EQ(cv::countNonZero(cut == kMaskedOut), 80 * 60);
  EXPECT_EQ(cut.at<unsigned char>(5, 5), kMaskedOut);
  EXPECT_EQ(cut.at<unsigned char>(5, 155), kUsable);
  const cv::Mat staged = cv::imread((dir / "ws" / "images" / "cut.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(staged.channels(), 3);
  EXPECT_FALSE(fs::exists(dir / "ws" / "masks" / "opaque.png.png"));
  // The mask file, not the (all transparent) alpha.
  EXPECT_EQ(cv::countNonZero(read_grey(dir / "ws" / "masks" / "own.png.png") == kMaskedOut), 80 * 60);
  for (const StagedImage& image : inputs.images)
    EXPECT_EQ(image.masked_by_alpha, image.name == "cut.png") << image.name;
}

TEST(PhotoMasks, MaskOfTheWrongSizeOrUnreadableNamesTheFileAndTheReason) {
  hos::testing::TempDir dir;
  const fs::path photos = dir / "photos";
  write_photos(photos, 3, 160, 120);
  cv::imwrite((photos / "p1.jpg.png").string(), top_left_masked(100, 100));
  try {
    prepare_images(photos, dir / "ws" / "images", SfmOptions{}, null_reporter());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), (photos / "p1.jpg.png").string());
    EXPECT_THAT(e.reason(), HasSubstr("100x100"));
    EXPECT_THAT(e.reason(), HasSubstr("160x120"));
  }
  std::ofstream(photos / "p1.jpg.png") << "not a picture";
  try {
    prepare_images(photos, dir / "ws" / "images", SfmOptions{}, null_reporter());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), (photos / "p1.jpg.png").string());
    EXPECT_THAT(e.reason(), HasSubstr("cannot be read"));
  }
  SfmOptions options;
  options.masks = (dir / "missing").string();
  EXPECT_THROW(prepare_images(photos, dir / "ws" / "images", options, null_reporter()), InputError);
}

TEST(PhotoMasks, MasksThatFitNoPhotoAreNamed) {
  hos::testing::TempDir dir;
  write_photos(dir / "photos", 3, 160, 120);
  fs::create_directories(dir / "masks");
  cv::imwrite((dir / "masks" / "p0.png").string(), top_left_masked(160, 120));  // not COLMAP's name
  SfmOptions options;
  options.masks = (dir / "masks").string();
  hos::testing::MessageLog log;
  const ImageInputs inputs = prepare_images(dir / "photos", dir / "ws" / "images", options, log);
  EXPECT_EQ(inputs.masked_photos(), 0);
  EXPECT_TRUE(inputs.mask_folder.empty());
  EXPECT_THAT(log.all(), HasSubstr("masks: 0 of 3 photos have a mask"));
  EXPECT_THAT(log.warnings(), HasSubstr("p0.png"));
}

TEST(PhotoMasks, MaskBesideAPhotoIsOnlyThePhotoNamePlusPng) {
  std::set<fs::path> files{"a/IMG_1.jpg", "a/IMG_1.jpg.png", "a/IMG_2.png", "a/IMG_2.jpg", "a/x.png.png"};
  EXPECT_TRUE(is_mask_beside_photo("a/IMG_1.jpg.png", files));
  EXPECT_FALSE(is_mask_beside_photo("a/IMG_2.png", files));  // a photo of its own
  EXPECT_FALSE(is_mask_beside_photo("a/IMG_1.jpg", files));
  EXPECT_FALSE(is_mask_beside_photo("a/x.png.png", files));  // x.png is not listed
}

TEST(PhotoMasks, FeatureExtractionGetsTheMaskFolderOnlyWhenPhotosHaveMasks) {
  ColmapRunContext context;
  context.database = "db";
  context.images = "images";
  ExtractionRun run;
  run.names = {"a.jpg"};
  const auto has_mask_path = [](const ColmapStep& step, const std::string& folder) {
    for (std::size_t i = 0; i + 1 < step.args.size(); ++i) {
      if (step.args[i] == "--ImageReader.mask_path") return step.args[i + 1] == folder;
    }
    return false;
  };
  EXPECT_FALSE(has_mask_path(feature_extraction_step(context, run, "list", SfmPlan{}, SfmOptions{}), ""));
  context.masks = "ws/sfm/masks";
  EXPECT_TRUE(has_mask_path(feature_extraction_step(context, run, "list", SfmPlan{}, SfmOptions{}), "ws/sfm/masks"));
}

// Radial distortion keeps lines through the principal point straight: a
// mask that excludes the left half of a distorted photo excludes exactly
// the left half of the undistorted one. Its corners, beyond the photo's
// edge after undistortion (barrel distortion), are masked.
TEST(PhotoMasks, UndistortedMaskFollowsTheCameraModel) {
  hos::testing::TempDir dir;
  SparseModel distorted, pinhole;
  Camera radial;
  radial.id = 1;
  radial.model = CameraModel::kSimpleRadial;
  radial.width = 200;
  radial.height = 100;
  radial.params = {150.0, 100.0, 50.0, -0.2};
  distorted.cameras[1] = radial;
  pinhole.cameras[1] = Camera::pinhole(1, 200, 100, 150.0, 150.0, 100.0, 50.0);
  ImageRecord image;
  image.id = 1;
  image.camera_id = 1;
  image.name = "sub/a.jpg";
  distorted.images[1] = image;
  pinhole.images[1] = image;
  cv::Mat mask(100, 200, CV_8U, cv::Scalar(255));
  mask.colRange(0, 100).setTo(0);
  write_mask(mask, mask_file(dir / "masks", "sub/a.jpg"));
  EXPECT_EQ(undistort_masks(distorted, pinhole, dir / "masks", dir / "out"), 1);
  const cv::Mat out = read_mask(mask_file(dir / "out", "sub/a.jpg"), 200, 100, "sub/a.jpg");
  for (int y = 20; y < 80; ++y) {
    EXPECT_EQ(out.at<unsigned char>(y, 99), kMaskedOut) << y;
    EXPECT_EQ(out.at<unsigned char>(y, 100), kUsable) << y;
  }
  // Barrel distortion (k < 0) pulls the pinhole image's corners inwards in
  // the photo: the corner's ray meets the photo inside it, the far side of
  // the mask.
  const Eigen::Vector2d corner = *radial.project({(199.5 - 100.0) / 150.0, (0.5 - 50.0) / 150.0, 1.0});
  EXPECT_LT(corner.x(), 199.5);
  EXPECT_EQ(out.at<unsigned char>(0, 199), mask.at<unsigned char>(int(corner.y()), int(corner.x())));
  // No mask file: nothing written.
  fs::remove(mask_file(dir / "masks", "sub/a.jpg"));
  EXPECT_EQ(undistort_masks(distorted, pinhole, dir / "masks", dir / "out2"), 0);
}

}  // namespace
}  // namespace hos::sfm
