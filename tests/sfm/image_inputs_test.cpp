#include "sfm/image_inputs.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "core/json_report.h"
#include "sfm/photo_format.h"
#include "sfm/sfm.h"
#include "sfm/sfm_report.h"
#include "tests/sfm/jpeg_fixtures.h"
#include "tests/support/test_support.h"

namespace hos::sfm {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

using testing::write_bytes;

void write_good_jpegs(const fs::path& folder, int count, int width = 120, int height = 90) {
  for (int i = 0; i < count; ++i) {
    cv::imwrite((folder / ("good" + std::to_string(i) + ".jpg")).string(), testing::gradient_image(width, height));
  }
}

// Captures warnings so tests can check that each skipped file is named.
class RecordingReporter : public Reporter {
 public:
  void log(LogLevel level, std::string_view message) override {
    if (level == LogLevel::kWarning) warnings.emplace_back(message);
  }
  std::vector<std::string> warnings;
};

TEST(ImageInputs, MissingFolderIsInputError) {
  hos::testing::TempDir dir;
  try {
    prepare_images(dir / "nope", dir / "staged", SfmOptions{}, null_reporter());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("does not exist"));
  }
}

TEST(ImageInputs, EmptyFolderSaysNoPhotos) {
  hos::testing::TempDir dir;
  fs::create_directories(dir / "photos");
  try {
    prepare_images(dir / "photos", dir / "staged", SfmOptions{}, null_reporter());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("contains no photos"));
  }
}

TEST(ImageInputs, TextFilesAreSkippedByNameThenTooFewIsAnError) {
  hos::testing::TempDir dir;
  fs::create_directories(dir / "photos");
  for (const char* name : {"a.txt", "b.md", "c.jpg"}) {
    std::ofstream(dir / "photos" / name) << "this is not a photo\n";
  }
  RecordingReporter reporter;
  try {
    prepare_images(dir / "photos", dir / "staged", SfmOptions{}, reporter);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("only 0 usable photo"));
    EXPECT_THAT(e.what(), HasSubstr("a.txt"));
    EXPECT_THAT(e.what(), HasSubstr("c.jpg"));
  }
  ASSERT_EQ(reporter.warnings.size(), 3u);
  EXPECT_THAT(reporter.warnings[2], HasSubstr("c.jpg"));
}

TEST(ImageInputs, CorruptZeroByteAndTinyFilesAreSkippedTheRestStaged) {
  hos::testing::TempDir dir;
  const fs::path photos = dir / "photos";
  fs::create_directories(photos);
  write_good_jpegs(photos, 3);
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", testing::gradient_image(200, 150), jpeg);
  jpeg.resize(jpeg.size() / 2);
  write_bytes(photos / "truncated.jpg", jpeg);
  std::vector<std::uint8_t> png;
  cv::imencode(".png", testing::gradient_image(200, 150), png);
  png.resize(png.size() / 2);
  write_bytes(photos / "truncated.png", png);
  write_bytes(photos / "empty.jpg", {});
  cv::imwrite((photos / "tiny.png").string(), testing::gradient_image(20, 20));
  std::ofstream(photos / ".hidden") << "ignored";

  RecordingReporter reporter;
  const ImageInputs inputs = prepare_images(photos, dir / "staged", SfmOptions{}, reporter);
  ASSERT_EQ(inputs.images.size(), 3u);
  EXPECT_EQ(inputs.images[0].name, "good0.jpg");
  EXPECT_TRUE(inputs.same_camera());
  ASSERT_EQ(inputs.skipped.size(), 4u);
  std::map<std::string, std::string> reasons;
  for (const auto& s : inputs.skipped) reasons[s.file.filename().string()] = s.reason;
  EXPECT_THAT(reasons["empty.jpg"], HasSubstr("0 bytes"));
  EXPECT_THAT(reasons["truncated.jpg"], HasSubstr("truncated"));
  EXPECT_THAT(reasons["truncated.png"], HasSubstr("cannot be decoded"));
  EXPECT_THAT(reasons["tiny.png"], HasSubstr("too small"));
  EXPECT_EQ(reporter.warnings.size(), 4u);
  for (int i = 0; i < 3; ++i) {
    const fs::path staged = dir / "staged" / ("good" + std::to_string(i) + ".jpg");
    EXPECT_TRUE(fs::exists(staged)) << staged;
    EXPECT_FALSE(inputs.images[i].rewritten);
  }
  EXPECT_FALSE(fs::exists(dir / "staged" / "truncated.jpg"));
}

TEST(ImageInputs, ExifOrientationIsAppliedAndLargePhotosDownscaled) {
  hos::testing::TempDir dir;
  const fs::path photos = dir / "photos";
  fs::create_directories(photos);
  write_good_jpegs(photos, 2, 200, 100);
  const cv::Mat source = testing::gradient_image(200, 100);
  write_bytes(photos / "portrait.jpg", testing::jpeg_with_exif(source, 6, 24.0, true));
  SfmOptions options;
  options.max_image_size = 150;
  const ImageInputs inputs = prepare_images(photos, dir / "staged", options, null_reporter());
  ASSERT_EQ(inputs.images.size(), 3u);
  const StagedImage& portrait = inputs.images[2];
  ASSERT_EQ(portrait.name, "portrait.jpg");
  EXPECT_TRUE(portrait.rewritten);
  // Orientation 6: turned 90 degrees clockwise, then downscaled to 150 long side.
  EXPECT_EQ(portrait.width, 75);
  EXPECT_EQ(portrait.height, 150);
  EXPECT_FALSE(inputs.same_camera());
  const cv::Mat staged = cv::imread((dir / "staged" / "portrait.jpg").string(), cv::IMREAD_COLOR);
  ASSERT_EQ(staged.cols, 75);
  ASSERT_EQ(staged.rows, 150);
  // After a clockwise turn the source's left column (x = 0, blue channel 0)
  // becomes the top row, and its top row (green 0) the right column.
  EXPECT_LT(staged.at<cv::Vec3b>(2, 37)[0], 30);
  EXPECT_GT(staged.at<cv::Vec3b>(147, 37)[0], 220);
  EXPECT_LT(staged.at<cv::Vec3b>(75, 72)[1], 30);
  EXPECT_GT(staged.at<cv::Vec3b>(75, 2)[1], 220);
  // The originals are untouched.
  EXPECT_EQ(cv::imread((photos / "good0.jpg").string()).cols, 200);
  EXPECT_EQ(inputs.images[0].width, 150);
}

// The run report's thumbnails: one per usable photo, upright, kThumbnailWidth
// wide; none for a skipped file.
TEST(ImageInputs, ThumbnailsAreSmallUprightAndOnlyOfUsablePhotos) {
  hos::testing::TempDir dir;
  const fs::path photos = dir / "photos";
  fs::create_directories(photos);
  write_good_jpegs(photos, 2, 640, 480);
  write_bytes(photos / "portrait.jpg", testing::jpeg_with_exif(testing::gradient_image(640, 480), 6, 24.0, true));
  std::ofstream(photos / "notes.txt") << "not a photo";
  const ImageInputs inputs = prepare_images(photos, dir / "staged", SfmOptions{}, null_reporter(), dir / "thumbs");
  ASSERT_EQ(inputs.images.size(), 3u);
  const cv::Mat landscape = cv::imread((dir / "thumbs" / "good0.jpg.jpg").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(landscape.empty());
  EXPECT_EQ(landscape.cols, kThumbnailWidth);
  EXPECT_EQ(landscape.rows, kThumbnailWidth * 480 / 640);
  const cv::Mat portrait = cv::imread((dir / "thumbs" / "portrait.jpg.jpg").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(portrait.empty());
  EXPECT_EQ(portrait.cols, kThumbnailWidth);
  EXPECT_EQ(portrait.rows, kThumbnailWidth * 640 / 480);
  EXPECT_LT(fs::file_size(dir / "thumbs" / "portrait.jpg.jpg"), 20000u);
  EXPECT_FALSE(fs::exists(dir / "thumbs" / "notes.txt.jpg"));
}

TEST(ImageInputs, OrientationTableMatchesExifDefinition) {
  // A 2x3 image with distinct pixels; each orientation's upright result is
  // checked at its corners against the EXIF definition.
  cv::Mat m(2, 3, CV_8UC1);
  for (int i = 0; i < 6; ++i) m.data[i] = static_cast<std::uint8_t>(i);  // rows: 0 1 2 / 3 4 5
  auto corners = [](const cv::Mat& r) {
    return std::vector<int>{r.at<std::uint8_t>(0, 0), r.at<std::uint8_t>(0, r.cols - 1),
                            r.at<std::uint8_t>(r.rows - 1, 0), r.at<std::uint8_t>(r.rows - 1, r.cols - 1)};
  };
  EXPECT_EQ(corners(apply_exif_orientation(m, 1)), (std::vector<int>{0, 2, 3, 5}));
  EXPECT_EQ(corners(apply_exif_orientation(m, 2)), (std::vector<int>{2, 0, 5, 3}));
  EXPECT_EQ(corners(apply_exif_orientation(m, 3)), (std::vector<int>{5, 3, 2, 0}));
  EXPECT_EQ(corners(apply_exif_orientation(m, 4)), (std::vector<int>{3, 5, 0, 2}));
  EXPECT_EQ(corners(apply_exif_orientation(m, 5)), (std::vector<int>{0, 3, 2, 5}));
  EXPECT_EQ(corners(apply_exif_orientation(m, 6)), (std::vector<int>{3, 0, 5, 2}));
  EXPECT_EQ(corners(apply_exif_orientation(m, 7)), (std::vector<int>{5, 2, 3, 0}));
  EXPECT_EQ(corners(apply_exif_orientation(m, 8)), (std::vector<int>{2, 5, 0, 3}));
}

TEST(ImageInputs, SixteenBitPhotosAreStagedAsEightBits) {
  hos::testing::TempDir dir;
  fs::create_directories(dir / "photos");
  write_good_jpegs(dir / "photos", 2);
  cv::Mat deep;
  testing::gradient_image(120, 90).convertTo(deep, CV_16U, 257.0);  // 8 -> 16 bits, same picture
  ASSERT_TRUE(cv::imwrite((dir / "photos" / "deep.png").string(), deep));
  ASSERT_TRUE(cv::imwrite((dir / "photos" / "deep.tif").string(), deep));
  const ImageInputs inputs = prepare_images(dir / "photos", dir / "staged", SfmOptions{}, null_reporter());
  ASSERT_EQ(inputs.images.size(), 4u);
  for (const char* name : {"deep.png", "deep.tif"}) {
    const cv::Mat staged = cv::imread((dir / "staged" / name).string(), cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(staged.empty()) << name;
    EXPECT_EQ(staged.depth(), CV_8U) << name << " was staged with more than 8 bits (COLMAP cannot read it)";
    // The same picture: within one grey level of the 8-bit original.
    cv::Mat original = testing::gradient_image(120, 90), diff;
    cv::absdiff(staged, original, diff);
    double max_diff = 0.0;
    cv::minMaxLoc(diff.reshape(1), nullptr, &max_diff);
    EXPECT_LE(max_diff, 1.0) << name;
  }
}

TEST(ImageInputs, SymlinkLoopIsSkippedWithAWarning) {
  hos::testing::TempDir dir;
  fs::create_directories(dir / "photos");
  write_good_jpegs(dir / "photos", 3);
  fs::create_symlink("loop.jpg", dir / "photos" / "loop.jpg");  // points at itself
  fs::create_symlink(dir / "photos" / "b_link", dir / "photos" / "a_link");
  fs::create_symlink(dir / "photos" / "a_link", dir / "photos" / "b_link");
  RecordingReporter reporter;
  const ImageInputs inputs = prepare_images(dir / "photos", dir / "staged", SfmOptions{}, reporter);
  EXPECT_EQ(inputs.images.size(), 3u);
  EXPECT_EQ(inputs.skipped.size(), 3u);
  std::string warnings;
  for (const auto& w : reporter.warnings) warnings += w + "\n";
  EXPECT_THAT(warnings, HasSubstr("loop.jpg"));
  EXPECT_THAT(warnings, HasSubstr("a_link"));
}

// The value of an EXIF tag of a staged file, read back with exiv2; "" when absent.
std::string tag(const Exiv2::ExifData& exif, const char* key) {
  const auto it = exif.findKey(Exiv2::ExifKey(key));
  return it == exif.end() ? std::string() : it->toString();
}

double rational_tag(const Exiv2::ExifData& exif, const char* key, long n = 0) {
  const auto it = exif.findKey(Exiv2::ExifKey(key));
  if (it == exif.end()) return -1.0;
  const Exiv2::Rational r = it->toRational(n);
  return double(r.first) / double(r.second);
}

testing::PhoneExif phone_with_gps() {
  testing::PhoneExif fields;
  fields.latitude_deg = 46.5191;
  fields.longitude_deg = 6.5668;
  fields.altitude_m = 372.5;
  fields.focal_plane_x_resolution = 4000.0;
  return fields;
}

// Every staged copy (turned, downscaled, 16 to 8 bits) carries the photo's
// EXIF, with Orientation 1 and the copy's own pixel size.
TEST(ImageInputs, StagedCopiesCarryThePhotosExif) {
  hos::testing::TempDir dir;
  const fs::path photos = dir / "photos";
  fs::create_directories(photos);
  testing::PhoneExif turned = phone_with_gps();
  turned.orientation = 6;
  write_bytes(photos / "turned.jpg", testing::jpeg_with_phone_exif(testing::gradient_image(200, 100), turned));
  write_bytes(photos / "large.jpg", testing::jpeg_with_phone_exif(testing::gradient_image(400, 300), phone_with_gps()));
  cv::Mat deep;
  testing::gradient_image(200, 150).convertTo(deep, CV_16U, 257.0);
  for (const char* name : {"deep.png", "deep.tif"}) {
    ASSERT_TRUE(cv::imwrite((photos / name).string(), deep));
    testing::write_phone_exif(photos / name, phone_with_gps());
  }
  SfmOptions options;
  options.max_image_size = 300;
  const ImageInputs inputs = prepare_images(photos, dir / "staged", options, null_reporter());
  ASSERT_EQ(inputs.images.size(), 4u);
  for (const StagedImage& image : inputs.images) {
    SCOPED_TRACE(image.name);
    EXPECT_TRUE(image.rewritten);
    const fs::path staged = dir / "staged" / image.name;
    ASSERT_FALSE(fs::is_symlink(staged));
    const Exiv2::ExifData exif = testing::read_exif_data(staged);
    EXPECT_EQ(tag(exif, "Exif.Image.Orientation"), "1");
    EXPECT_EQ(tag(exif, "Exif.Image.Make"), "Apple");
    EXPECT_EQ(tag(exif, "Exif.Image.Model"), "iPhone 12");
    EXPECT_NEAR(rational_tag(exif, "Exif.Photo.FocalLength"), 4.2, 1e-9);
    EXPECT_EQ(tag(exif, "Exif.Photo.FocalLengthIn35mmFilm"), "26");
    EXPECT_EQ(tag(exif, "Exif.GPSInfo.GPSLatitudeRef"), "N");
    EXPECT_NEAR(rational_tag(exif, "Exif.GPSInfo.GPSLatitude", 0), 46.0, 1e-9);
    EXPECT_NEAR(rational_tag(exif, "Exif.GPSInfo.GPSAltitude"), 372.5, 1e-9);
    EXPECT_EQ(tag(exif, "Exif.Photo.PixelXDimension"), std::to_string(image.width));
    EXPECT_EQ(tag(exif, "Exif.Photo.PixelYDimension"), std::to_string(image.height));
    // What the stage reads from the copy is what it read from the photo.
    const ExifInfo info = read_exif(read_file_bytes(staged)).info();
    EXPECT_EQ(info.orientation, 1);
    ASSERT_TRUE(info.gps.has_value());
    EXPECT_NEAR(info.gps->latitude_deg, 46.5191, 1e-6);
  }
  const auto find = [&](const std::string& name) {
    return *std::find_if(inputs.images.begin(), inputs.images.end(),
                         [&](const StagedImage& i) { return i.name == name; });
  };
  EXPECT_EQ(find("turned.jpg").width, 100);
  EXPECT_EQ(find("turned.jpg").height, 200);
  EXPECT_EQ(find("large.jpg").width, 300);
  EXPECT_EQ(find("large.jpg").height, 225);
  // Pixels per inch on the sensor follow the downscaling (COLMAP's focal
  // length in pixels from FocalLength and FocalPlaneXResolution).
  EXPECT_NEAR(rational_tag(testing::read_exif_data(dir / "staged" / "large.jpg"), "Exif.Photo.FocalPlaneXResolution"),
              3000.0, 1e-6);
  EXPECT_NEAR(rational_tag(testing::read_exif_data(dir / "staged" / "turned.jpg"), "Exif.Photo.FocalPlaneXResolution"),
              4000.0, 1e-6);
  // The 16-bit photos stay lossless, now 8 bits.
  EXPECT_EQ(photo_format_of_file(dir / "staged" / "deep.png"), PhotoFormat::kPng);
  EXPECT_EQ(photo_format_of_file(dir / "staged" / "deep.tif"), PhotoFormat::kTiff);
  EXPECT_EQ(cv::imread((dir / "staged" / "deep.tif").string(), cv::IMREAD_UNCHANGED).depth(), CV_8U);
}

// COLMAP takes a GPS position prior only with an altitude: a photo without
// one is copied (not linked) with altitude 0, and the stage knows the
// altitude is made up. Photos with nothing to change stay links.
TEST(ImageInputs, GpsWithoutAltitudeIsCopiedWithAltitudeZero) {
  hos::testing::TempDir dir;
  const fs::path photos = dir / "photos";
  fs::create_directories(photos);
  testing::PhoneExif no_altitude = phone_with_gps();
  no_altitude.altitude_m.reset();
  write_bytes(photos / "no_altitude.jpg", testing::jpeg_with_phone_exif(testing::gradient_image(120, 90), no_altitude));
  write_bytes(photos / "full.jpg", testing::jpeg_with_phone_exif(testing::gradient_image(120, 90), phone_with_gps()));
  write_good_jpegs(photos, 1);
  const ImageInputs inputs = prepare_images(photos, dir / "staged", SfmOptions{}, null_reporter());
  ASSERT_EQ(inputs.images.size(), 3u);
  const StagedImage& missing = inputs.images[2];
  ASSERT_EQ(missing.name, "no_altitude.jpg");
  ASSERT_TRUE(missing.gps.has_value());
  EXPECT_FALSE(missing.gps->altitude_m.has_value());
  EXPECT_TRUE(missing.gps_altitude_missing);
  EXPECT_FALSE(missing.rewritten);
  const fs::path staged = dir / "staged" / "no_altitude.jpg";
  ASSERT_FALSE(fs::is_symlink(staged));
  const Exiv2::ExifData exif = testing::read_exif_data(staged);
  EXPECT_NEAR(rational_tag(exif, "Exif.GPSInfo.GPSAltitude"), 0.0, 1e-12);
  EXPECT_EQ(tag(exif, "Exif.GPSInfo.GPSAltitudeRef"), "0");
  EXPECT_NEAR(rational_tag(exif, "Exif.GPSInfo.GPSLongitude", 0), 6.0, 1e-12);
  EXPECT_NEAR(rational_tag(exif, "Exif.Photo.FocalLength"), 4.2, 1e-9);
  // The pixels are the photo's own (not re-encoded).
  cv::Mat diff;
  cv::absdiff(cv::imread(staged.string()), cv::imread((photos / "no_altitude.jpg").string()), diff);
  EXPECT_EQ(cv::countNonZero(diff.reshape(1)), 0);
  EXPECT_FALSE(inputs.images[0].gps_altitude_missing);  // full.jpg
  EXPECT_TRUE(fs::is_symlink(dir / "staged" / "full.jpg"));
  EXPECT_TRUE(fs::is_symlink(dir / "staged" / "good0.jpg"));
}

// A HEIC photo is decoded (libheif turns it upright from its irot; the EXIF
// orientation, which says the same, is not applied again) and staged as a
// JPEG with its EXIF; one saved with a .jpg name is read by its content.
TEST(ImageInputs, HeicPhotosAreStagedAsUprightJpegsWithTheirExif) {
  testing::PhoneExif fields;
  fields.orientation = 6;
  const std::vector<std::uint8_t> heic = testing::heic_with_exif(testing::gradient_image(200, 100), 6, fields);
  if (heic.empty()) GTEST_SKIP() << "libheif has no HEVC encoder here";
  hos::testing::TempDir dir;
  const fs::path photos = dir / "photos";
  fs::create_directories(photos);
  write_bytes(photos / "IMG_0001.HEIC", heic);
  write_bytes(photos / "saved_as.jpg", heic);
  std::vector<std::uint8_t> png;
  cv::imencode(".png", testing::gradient_image(120, 90), png);
  write_bytes(photos / "png_named.jpg", png);
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", testing::gradient_image(120, 90), jpeg);
  write_bytes(photos / "no_extension", jpeg);
  RecordingReporter reporter;
  const ImageInputs inputs = prepare_images(photos, dir / "staged", SfmOptions{}, reporter);
  EXPECT_TRUE(reporter.warnings.empty()) << reporter.warnings.front();
  ASSERT_EQ(inputs.images.size(), 4u);
  EXPECT_EQ(inputs.images[0].name, "IMG_0001.HEIC.jpg");
  EXPECT_EQ(inputs.images[1].name, "no_extension");
  EXPECT_EQ(inputs.images[2].name, "png_named.jpg");
  EXPECT_EQ(inputs.images[3].name, "saved_as.jpg");
  for (const StagedImage* image : {&inputs.images[0], &inputs.images[3]}) {
    SCOPED_TRACE(image->name);
    EXPECT_EQ(image->width, 100);
    EXPECT_EQ(image->height, 200);
    ASSERT_TRUE(image->focal_length_mm.has_value());
    EXPECT_NEAR(*image->focal_length_mm, 4.2, 1e-9);
    EXPECT_EQ(image->camera_model, "iPhone 12");
    const fs::path staged = dir / "staged" / image->name;
    EXPECT_EQ(photo_format_of_file(staged), PhotoFormat::kJpeg);
    const cv::Mat pixels = cv::imread(staged.string(), cv::IMREAD_COLOR);
    ASSERT_EQ(pixels.cols, 100);
    ASSERT_EQ(pixels.rows, 200);
    // Turned clockwise once: the source's left column (blue 0) is the top
    // row, its top row (green 0) the right column.
    EXPECT_LT(pixels.at<cv::Vec3b>(3, 50)[0], 50);
    EXPECT_GT(pixels.at<cv::Vec3b>(196, 50)[0], 200);
    EXPECT_LT(pixels.at<cv::Vec3b>(100, 96)[1], 50);
    EXPECT_GT(pixels.at<cv::Vec3b>(100, 3)[1], 200);
    const Exiv2::ExifData exif = testing::read_exif_data(staged);
    EXPECT_EQ(tag(exif, "Exif.Image.Orientation"), "1");
    EXPECT_NEAR(rational_tag(exif, "Exif.Photo.FocalLength"), 4.2, 1e-9);
    EXPECT_EQ(tag(exif, "Exif.Photo.PixelXDimension"), "100");
  }
}

// A phone's folder layout: photos only in DCIM/1xxAPPLE/ subfolders, found
// with their relative paths as names (the same file name in two folders
// stays two photos); hidden folders, hos workspaces and the folders given
// as excluded are left out.
TEST(ImageInputs, PhotosInSubfoldersAreStagedUnderTheirRelativeNames) {
  hos::testing::TempDir dir;
  const fs::path photos = dir / "photos";
  for (const char* sub : {"DCIM/100APPLE", "DCIM/101APPLE", ".hidden", "old_run/sfm", "excluded"}) {
    fs::create_directories(photos / sub);
  }
  for (const char* name : {"DCIM/100APPLE/IMG_1.jpg", "DCIM/100APPLE/IMG_2.jpg", "DCIM/101APPLE/IMG_1.jpg",
                           ".hidden/IMG_9.jpg", "old_run/sfm/thumb.jpg", "excluded/IMG_8.jpg"}) {
    cv::imwrite((photos / name).string(), testing::gradient_image(120, 90));
  }
  std::ofstream(photos / "old_run" / "run.json") << "{}";
  // Staging inside the photo folder, twice: the staged files of the first
  // run are not taken for photos by the second.
  for (int run = 0; run < 2; ++run) {
    const ImageInputs inputs =
        prepare_images(photos, photos / "staged", SfmOptions{}, null_reporter(), dir / "thumbs", {photos / "excluded"});
    ASSERT_EQ(inputs.images.size(), 3u);
    EXPECT_TRUE(inputs.skipped.empty());
    EXPECT_EQ(inputs.images[0].name, "DCIM/100APPLE/IMG_1.jpg");
    EXPECT_EQ(inputs.images[1].name, "DCIM/100APPLE/IMG_2.jpg");
    EXPECT_EQ(inputs.images[2].name, "DCIM/101APPLE/IMG_1.jpg");
    for (const StagedImage& image : inputs.images) {
      EXPECT_EQ(cv::imread((photos / "staged" / image.name).string()).cols, 120) << image.name;
      EXPECT_EQ(cv::imread((dir / "thumbs" / (image.name + ".jpg")).string()).cols, kThumbnailWidth) << image.name;
    }
  }
}

// The files the stage reads: photos by content, whatever their names; not
// sidecars, notes or hidden files (the pipeline fingerprints this list).
TEST(ImageInputs, PhotoFilesAreThePhotosByContent) {
  hos::testing::TempDir dir;
  const fs::path photos = dir / "photos";
  fs::create_directories(photos / "sub");
  write_good_jpegs(photos, 1);
  cv::imwrite((photos / "sub" / "b.png").string(), testing::gradient_image(40, 30));
  std::vector<std::uint8_t> jpeg;
  cv::imencode(".jpg", testing::gradient_image(40, 30), jpeg);
  write_bytes(photos / "IMG_7.HEIC", jpeg);  // a JPEG, whatever its name says
  std::ofstream(photos / "good0.xmp") << "<x:xmpmeta/>";
  std::ofstream(photos / "IMG_7.AAE") << "<?xml version=\"1.0\"?>";
  std::ofstream(photos / "notes.txt") << "a note";
  std::ofstream(photos / ".DS_Store") << "finder";
  write_bytes(photos / "empty.jpg", {});
  const std::vector<fs::path> expected{photos / "IMG_7.HEIC", photos / "good0.jpg", photos / "sub" / "b.png"};
  EXPECT_EQ(list_photo_files(photos), expected);
  EXPECT_EQ(list_input_files(photos).size(), 7u);  // all but .DS_Store
  EXPECT_TRUE(list_photo_files(dir / "missing").empty());
}

// File names are bytes: a Latin-1 name (an unzipped Windows archive) is
// staged, and the reports that name it are written and read back.
TEST(ImageInputs, NonUtf8FileNamesSurviveStagingAndTheReports) {
  hos::testing::TempDir dir;
  const fs::path photos = dir / "photos";
  fs::create_directories(photos);
  write_good_jpegs(photos, 2);
  const std::string latin1 = "caf\xE9.jpg";  // "café.jpg" in Latin-1: not UTF-8
  cv::imwrite((photos / latin1).string(), testing::gradient_image(120, 90));
  std::ofstream(photos / "notes\xE9.txt") << "not a photo";
  const ImageInputs inputs = prepare_images(photos, dir / "staged", SfmOptions{}, null_reporter(), dir / "thumbs");
  ASSERT_EQ(inputs.images.size(), 3u);
  EXPECT_EQ(inputs.images[0].name, latin1);
  EXPECT_TRUE(fs::exists(dir / "thumbs" / (latin1 + ".jpg")));

  SfmResult result;
  result.images_given = 3;
  result.skipped = inputs.skipped;
  result.unregistered = {latin1};
  ASSERT_NO_THROW(write_sfm_report(result, dir / "report.json"));
  const nlohmann::json report = nlohmann::json::parse(hos::testing::read_text(dir / "report.json"));
  EXPECT_EQ(report["unregistered"][0].get<std::string>().substr(0, 3), "caf");

  // The other stages' reports share one writer (mvs, recon, texture).
  nlohmann::ordered_json j;
  j["views"] = {{{"name", latin1}}};
  ASSERT_NO_THROW(write_json_report(dir / "mvs_report.json", j));
  EXPECT_EQ(nlohmann::json::parse(hos::testing::read_text(dir / "mvs_report.json"))["views"][0]["name"]
                .get<std::string>()
                .substr(0, 3),
            "caf");
}

}  // namespace
}  // namespace hos::sfm
