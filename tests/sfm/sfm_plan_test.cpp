#include "sfm/sfm_plan.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/error.h"

namespace hos::sfm {
namespace {
using ::testing::HasSubstr;

PhotoSetFacts photos(int count, int with_gps = 0, int longest_side_px = 3072) {
  return {count, with_gps, longest_side_px};
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
  EXPECT_EQ(plan.sift_max_image_size, 2400);
  EXPECT_FALSE(plan.sift_upsample);
  plan = plan_sfm(photos(36, 0, 800), options);
  EXPECT_TRUE(plan.sift_upsample);  // 800 px < sift_upsample_below 1200
  options.sift_upsample_below = 0;
  EXPECT_FALSE(plan_sfm(photos(36, 0, 800), options).sift_upsample);
  // No bound: COLMAP gets the largest photo's side.
  options.sift_max_image_size = 0;
  EXPECT_EQ(plan_sfm(photos(11, 0, 4000), options).sift_max_image_size, 4000);
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
