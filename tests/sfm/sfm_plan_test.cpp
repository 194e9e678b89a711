#include "sfm/sfm_plan.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>

#include "core/error.h"
#include "core/reporter.h"

namespace hos::sfm {
namespace {
using ::testing::HasSubstr;

// count photos of one camera, longest side first (4:3).
PhotoSetFacts photos(int count, int with_gps = 0, int longest_side_px = 3072) {
  CameraGroup group;
  group.width = longest_side_px;
  group.height = longest_side_px * 3 / 4;
  for (int i = 0; i < count; ++i) group.names.push_back(format_message("p", i, ".jpg"));
  return {count, with_gps, 0, {group}};
}

StagedImage staged(const std::string& name,
                   int width,
                   int height,
                   std::optional<double> focal = std::nullopt,
                   const std::string& model = "") {
  StagedImage image;
  image.name = name;
  image.width = width;
  image.height = height;
  image.focal_length_mm = focal;
  image.camera_model = model;
  return image;
}

// 23 small photos and one large one, as a user might mix them.
std::vector<StagedImage> small_photos_and_one_large() {
  std::vector<StagedImage> images;
  images.reserve(24);
  for (int i = 0; i < 23; ++i) images.push_back(staged(format_message("small", i, ".jpg"), 400, 300));
  images.push_back(staged("large.jpg", 1600, 1200));
  return images;
}

const ExtractionRun& run_holding(const SfmPlan& plan, const std::string& name) {
  for (const ExtractionRun& run : plan.extractions) {
    if (std::find(run.names.begin(), run.names.end(), name) != run.names.end()) return run;
  }
  throw std::runtime_error(name + " is in no extraction run");
}

TEST(SfmPlan, AutoMatcherFollowsPhotoCountAndGps) {
  const SfmOptions options;  // exhaustive_max_images 30
  EXPECT_EQ(plan_sfm(photos(11), options).matcher, "exhaustive");
  EXPECT_EQ(plan_sfm(photos(30), options).matcher, "exhaustive");
  // Over the limit: a tree from the photos, or positions when every photo has one.
  EXPECT_EQ(plan_sfm(photos(31), options).matcher, "vocab_tree");
  EXPECT_EQ(plan_sfm(photos(100, 100), options).matcher, "spatial");
  EXPECT_EQ(plan_sfm(photos(100, 99), options).matcher, "vocab_tree");
  // Few photos are matched exhaustively even when they carry GPS.
  EXPECT_EQ(plan_sfm(photos(20, 20), options).matcher, "exhaustive");
  EXPECT_THAT(plan_sfm(photos(100), options).matcher_reason, HasSubstr("100 photos > sfm.exhaustive_max_images (30)"));
}

TEST(SfmPlan, ExplicitMatcherAndLimitWin) {
  SfmOptions options;
  options.matcher = "sequential";
  EXPECT_EQ(plan_sfm(photos(11), options).matcher, "sequential");
  EXPECT_EQ(plan_sfm(photos(11), options).matcher_reason, "sfm.matcher");
  options.matcher = "auto";
  options.exhaustive_max_images = 10;
  EXPECT_EQ(plan_sfm(photos(11), options).matcher, "vocab_tree");
}

TEST(SfmPlan, FeaturesFallWithPhotoCount) {
  EXPECT_EQ(features_for_photo_count(3), 4096);
  EXPECT_EQ(features_for_photo_count(20), 4096);
  EXPECT_EQ(features_for_photo_count(36), 3072);  // 4096 sqrt(20/36) = 3053
  EXPECT_EQ(features_for_photo_count(100), 2048);
  EXPECT_EQ(features_for_photo_count(5000), 2048);
  for (int n = 1; n < 200; ++n) {
    EXPECT_LE(features_for_photo_count(n + 1), features_for_photo_count(n)) << n;
    EXPECT_EQ(features_for_photo_count(n) % 256, 0) << n;
  }
}

TEST(SfmPlan, FeatureAndMatchBudgets) {
  SfmOptions options;
  SfmPlan plan = plan_sfm(photos(36), options);
  EXPECT_EQ(plan.max_num_features, 3072);
  EXPECT_EQ(plan.max_num_matches, 1536);
  options.max_num_features = 8192;
  options.max_num_matches = 1000;
  plan = plan_sfm(photos(36), options);
  EXPECT_EQ(plan.max_num_features, 8192);
  EXPECT_EQ(plan.max_num_matches, 1000);
}

TEST(SfmPlan, SiftSizeIsBoundedAndSmallPhotosAreUpsampled) {
  SfmOptions options;
  SfmPlan plan = plan_sfm(photos(11, 0, 3072), options);
  ASSERT_EQ(plan.extractions.size(), 1u);
  EXPECT_EQ(plan.extractions[0].sift_max_image_size, 2400);
  EXPECT_FALSE(plan.extractions[0].sift_upsample);
  EXPECT_EQ(plan.extractions[0].names.size(), 11u);
  plan = plan_sfm(photos(36, 0, 800), options);
  EXPECT_TRUE(plan.extractions[0].sift_upsample);  // 800 px < sift_upsample_below 1200
  options.sift_upsample_below = 0;
  EXPECT_FALSE(plan_sfm(photos(36, 0, 800), options).extractions[0].sift_upsample);
  // No bound: COLMAP gets the largest photo's side.
  options.sift_max_image_size = 0;
  EXPECT_EQ(plan_sfm(photos(11, 0, 4000), options).extractions[0].sift_max_image_size, 4000);
}

// One 1600x1200 photo among 400x300 ones used to turn off the upsampled
// octave for all of them (6 of 24 registered): each camera group now has
// its own run and SIFT plan.
TEST(SfmPlan, OneLargePhotoKeepsTheSmallOnesUpsampled) {
  const SfmOptions options;
  const SfmPlan plan = plan_sfm(photo_set_facts(small_photos_and_one_large(), "auto"), options);
  ASSERT_EQ(plan.extractions.size(), 2u);
  const ExtractionRun& small = run_holding(plan, "small0.jpg");
  EXPECT_EQ(small.names.size(), 23u);
  EXPECT_TRUE(small.sift_upsample);
  EXPECT_TRUE(small.single_camera);
  const ExtractionRun& large = run_holding(plan, "large.jpg");
  EXPECT_EQ(large.names.size(), 1u);
  EXPECT_FALSE(large.sift_upsample);  // 1600 px >= sift_upsample_below 1200
  EXPECT_EQ(large.sift_max_image_size, 2400);
}

// Frames of two videos without EXIF: one camera per size, not per photo.
TEST(SfmPlan, PhotosOfTwoSizesWithoutExifGetOneCameraPerSize) {
  std::vector<StagedImage> images;
  images.reserve(12);
  for (int i = 0; i < 6; ++i) images.push_back(staged(format_message("a", i, ".png"), 640, 480));
  for (int i = 0; i < 6; ++i) images.push_back(staged(format_message("b", i, ".png"), 800, 600));
  const PhotoSetFacts facts = photo_set_facts(images, "auto");
  ASSERT_EQ(facts.groups.size(), 2u);
  EXPECT_EQ(facts.groups[0].names.size(), 6u);
  EXPECT_EQ(facts.groups[0].width, 640);
  const SfmPlan plan = plan_sfm(facts, SfmOptions{});
  ASSERT_EQ(plan.extractions.size(), 2u);
  for (const ExtractionRun& run : plan.extractions) {
    EXPECT_TRUE(run.single_camera);
    EXPECT_EQ(run.names.size(), 6u);
  }
}

TEST(CameraGroups, SplitByFocalLengthAndModelButNotByName) {
  const std::vector<StagedImage> images{staged("DCIM/100APPLE/IMG_1.JPG", 4032, 3024, 4.2, "iPhone 12"),
                                        staged("DCIM/100APPLE/IMG_2.JPG", 4032, 3024, 4.2, "iPhone 12"),
                                        staged("IMG_3.JPG", 4032, 3024, 6.0, "iPhone 12"),
                                        staged("IMG_4.JPG", 4032, 3024, 4.2, "Pixel 7"),
                                        staged("IMG_5.JPG", 3024, 4032, 4.2, "iPhone 12")};
  const auto groups = camera_groups(images, "auto");
  ASSERT_EQ(groups.size(), 4u);
  EXPECT_EQ(groups[0].names, (std::vector<std::string>{"DCIM/100APPLE/IMG_1.JPG", "DCIM/100APPLE/IMG_2.JPG"}));
  EXPECT_THAT(groups[0].describe(), HasSubstr("2 photos 4032x3024, 4.2 mm, iPhone 12"));
  // camera_mode single: one camera per size whatever the EXIF says.
  const auto by_size = camera_groups(images, "single");
  ASSERT_EQ(by_size.size(), 2u);
  EXPECT_EQ(by_size[0].names.size(), 4u);
  EXPECT_EQ(by_size[1].names, (std::vector<std::string>{"IMG_5.JPG"}));
}

TEST(SfmPlan, LonePhotosAndPerImageModeShareRunsWithOneCameraEach) {
  SfmOptions options;
  std::vector<StagedImage> images{staged("a.jpg", 640, 480), staged("b.jpg", 500, 400), staged("c.jpg", 700, 500),
                                  staged("d.jpg", 640, 480), staged("e.jpg", 3000, 2000)};
  // a and d share a camera; b and c are alone and upsampled alike; e alone,
  // not upsampled.
  SfmPlan plan = plan_sfm(photo_set_facts(images, "auto"), options);
  ASSERT_EQ(plan.extractions.size(), 3u);
  EXPECT_TRUE(run_holding(plan, "a.jpg").single_camera);
  EXPECT_EQ(run_holding(plan, "a.jpg").names, (std::vector<std::string>{"a.jpg", "d.jpg"}));
  EXPECT_EQ(run_holding(plan, "b.jpg").names, (std::vector<std::string>{"b.jpg", "c.jpg"}));
  EXPECT_FALSE(run_holding(plan, "b.jpg").single_camera);
  EXPECT_FALSE(run_holding(plan, "e.jpg").sift_upsample);
  // per_image: never a shared camera.
  options.camera_mode = "per_image";
  plan = plan_sfm(photo_set_facts(images, "per_image"), options);
  ASSERT_EQ(plan.extractions.size(), 2u);
  for (const ExtractionRun& run : plan.extractions) EXPECT_FALSE(run.single_camera);
  EXPECT_EQ(run_holding(plan, "a.jpg").names.size(), 4u);
}

// Photos with GPS but without altitude: COLMAP records a prior only with an
// altitude (staged as 0), so the spatial matcher must ignore height.
TEST(SfmPlan, SpatialMatchingIgnoresHeightWhenAltitudeIsMissing) {
  SfmOptions options;
  PhotoSetFacts facts = photos(48, 48);
  SfmPlan plan = plan_sfm(facts, options);
  ASSERT_EQ(plan.matcher, "spatial");
  EXPECT_FALSE(plan.spatial_ignore_z);
  facts.photos_without_altitude = 48;
  plan = plan_sfm(facts, options);
  ASSERT_EQ(plan.matcher, "spatial");
  EXPECT_TRUE(plan.spatial_ignore_z);
  EXPECT_THAT(plan.matcher_reason, HasSubstr("48 without altitude: matched by latitude and longitude only"));
}

TEST(SfmPlan, SpatialFallsBackWhenPriorsAreMissing) {
  SfmOptions options;
  const PhotoSetFacts facts = photos(48, 48);
  SfmPlan plan = plan_sfm(facts, options);
  EXPECT_FALSE(fall_back_from_spatial(plan, facts, 48, options));
  EXPECT_EQ(plan.matcher, "spatial");
  EXPECT_TRUE(fall_back_from_spatial(plan, facts, 0, options));
  EXPECT_EQ(plan.matcher, "vocab_tree");
  EXPECT_GT(plan.vocab_tree_words, 0);
  EXPECT_THAT(plan.matcher_reason, HasSubstr("only 0 of 48 photos have a position prior"));
  // An exhaustive plan stays.
  plan = plan_sfm(photos(12, 12), options);
  EXPECT_FALSE(fall_back_from_spatial(plan, photos(12, 12), 0, options));
  EXPECT_EQ(plan.matcher, "exhaustive");
}

TEST(SfmPlan, VocabularyTreeWordsFitTheFeatures) {
  SfmOptions options;
  const SfmPlan plan = plan_sfm(photos(100), options);
  ASSERT_EQ(plan.matcher, "vocab_tree");
  // 100 x 2048 features would make 2048 words; a set this small stays below
  // the word count at which COLMAP tunes its word index.
  EXPECT_EQ(plan.vocab_tree_words, 768);
  EXPECT_EQ(vocab_tree_words_for(40, 40 * 1000), 400);
  EXPECT_EQ(vocab_tree_words_for(10, 1000), 256);
  EXPECT_EQ(vocab_tree_words_for(1000, 1000LL * 2048), 20480);   // large sets: 100 features a word
  EXPECT_EQ(plan_sfm(photos(11), options).vocab_tree_words, 0);  // no tree for exhaustive matching
  options.vocab_tree_words = 5000;
  EXPECT_EQ(plan_sfm(photos(100), options).vocab_tree_words, 5000);
}

TEST(SfmOptions, NewOptionsAreValidated) {
  SfmOptions options;
  OptionSet set("sfm");
  register_options(set, options);
  set.apply_assignment("matcher", "vocab_tree");
  set.apply_assignment("sift_max_image_size", "1600");
  set.apply_assignment("ba_global_ratio", "1.4");
  EXPECT_EQ(options.matcher, "vocab_tree");
  EXPECT_EQ(options.sift_max_image_size, 1600);
  EXPECT_DOUBLE_EQ(options.ba_global_ratio, 1.4);
  EXPECT_THROW(set.apply_assignment("matcher", "nearest"), ConfigError);
  EXPECT_THROW(set.apply_assignment("ba_global_ratio", "0.5"), ConfigError);
  options.max_num_features = 50;
  EXPECT_THROW(options.validate(), ConfigError);
  options.max_num_features = 0;
  options.sift_max_image_size = 32;  // below min_image_size 64
  EXPECT_THROW(options.validate(), ConfigError);
  options.sift_max_image_size = 0;
  EXPECT_NO_THROW(options.validate());
}

}  // namespace
}  // namespace hos::sfm
