#include "sfm/colmap_steps.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "core/error.h"
#include "core/reporter.h"

namespace hos::sfm {
namespace {

// The value following --name in the step's arguments ("" if absent).
std::string arg(const ColmapStep& step, const std::string& name) {
  const auto it = std::find(step.args.begin(), step.args.end(), "--" + name);
  return it == step.args.end() || it + 1 == step.args.end() ? std::string() : *(it + 1);
}

ColmapRunContext context() {
  ColmapRunContext c;
  c.database = "ws/sfm/database.db";
  c.images = "ws/sfm/images";
  c.sparse = "ws/sfm/sparse";
  c.vocab_tree = "ws/sfm/vocab_tree.bin";
  c.num_images = 100;
  return c;
}

PhotoSetFacts facts(int photos, int with_gps, int longest_side_px) {
  CameraGroup group;
  group.width = longest_side_px;
  group.height = longest_side_px / 2;
  for (int i = 0; i < photos; ++i) group.names.push_back(format_message("p", i, ".jpg"));
  return {photos, with_gps, 0, {group}};
}

TEST(ColmapSteps, ExtractionIsBoundedAndUsesEveryCore) {
  const SfmOptions options;
  const SfmPlan plan = plan_sfm(facts(11, 0, 3072), options);
  const ColmapStep step = feature_extraction_step(context(), plan.extractions.at(0), "lists/0.txt", plan, options);
  EXPECT_EQ(step.command, "feature_extractor");
  EXPECT_EQ(arg(step, "SiftExtraction.max_image_size"), "2400");
  EXPECT_EQ(arg(step, "SiftExtraction.first_octave"), "0");
  EXPECT_EQ(arg(step, "SiftExtraction.max_num_features"), "4096");
  EXPECT_EQ(arg(step, "SiftExtraction.num_threads"), "-1");
  EXPECT_EQ(arg(step, "SiftExtraction.use_gpu"), "0");
  EXPECT_EQ(arg(step, "image_list_path"), "lists/0.txt");
  EXPECT_EQ(arg(step, "ImageReader.single_camera"), "1");
  EXPECT_EQ(step.total, 11);
  // Small photos keep COLMAP's upsampled first octave.
  const SfmPlan small = plan_sfm(facts(36, 0, 800), options);
  EXPECT_EQ(arg(feature_extraction_step(context(), small.extractions.at(0), "l", small, options),
                "SiftExtraction.first_octave"),
            "-1");
}

// A run per camera group: each with its own size plan and camera rule.
TEST(ColmapSteps, EachGroupIsExtractedWithItsOwnPlan) {
  SfmOptions options;
  std::vector<StagedImage> images(5);
  for (int i = 0; i < 5; ++i) {
    images[i].name = format_message("sub/dir/small", i, ".jpg");
    images[i].width = 400;
    images[i].height = 300;
  }
  images[4].name = "large.jpg";
  images[4].width = 1600;
  images[4].height = 1200;
  const SfmPlan plan = plan_sfm(photo_set_facts(images, "auto"), options);
  ASSERT_EQ(plan.extractions.size(), 2u);
  // In the order of the groups' first names: large.jpg, then sub/...
  const ColmapStep large = feature_extraction_step(context(), plan.extractions[0], "0.txt", plan, options);
  const ColmapStep small = feature_extraction_step(context(), plan.extractions[1], "1.txt", plan, options);
  EXPECT_EQ(arg(small, "SiftExtraction.first_octave"), "-1");
  EXPECT_EQ(arg(small, "ImageReader.single_camera"), "1");
  EXPECT_EQ(arg(large, "SiftExtraction.first_octave"), "0");
  EXPECT_EQ(arg(large, "ImageReader.single_camera"), "0");
  // Names from subfolders, one a line, relative to the image folder.
  EXPECT_EQ(image_list_file_text(plan.extractions[1]),
            "sub/dir/small0.jpg\nsub/dir/small1.jpg\nsub/dir/small2.jpg\nsub/dir/small3.jpg\n");
  EXPECT_EQ(image_list_file_text(plan.extractions[0]), "large.jpg\n");
}

TEST(ColmapSteps, ExhaustiveMatchingIsOneCommandWithTheMatchCap) {
  const SfmOptions options;
  const auto steps = matching_steps(context(), plan_sfm(facts(11, 0, 3072), options), options);
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_EQ(steps[0].command, "exhaustive_matcher");
  EXPECT_EQ(arg(steps[0], "SiftMatching.max_num_matches"), "2048");
  EXPECT_EQ(arg(steps[0], "SiftMatching.num_threads"), "-1");
  EXPECT_EQ(steps[0].total, 4);  // 100 images in blocks of 50: 2 x 2 blocks
}

TEST(ColmapSteps, VocabularyTreeIsBuiltFromThePhotosFirst) {
  const SfmOptions options;
  const SfmPlan plan = plan_sfm(facts(100, 0, 800), options);
  const auto steps = matching_steps(context(), plan, options);
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_EQ(steps[0].command, "vocab_tree_builder");
  EXPECT_EQ(arg(steps[0], "database_path"), "ws/sfm/database.db");
  EXPECT_EQ(arg(steps[0], "vocab_tree_path"), "ws/sfm/vocab_tree.bin");
  EXPECT_EQ(arg(steps[0], "num_visual_words"), std::to_string(plan.vocab_tree_words));
  // Fewer clusters per level than COLMAP's 256: the build is most of the cost.
  EXPECT_LT(std::stoi(arg(steps[0], "branching")), 256);
  EXPECT_EQ(steps[1].command, "vocab_tree_matcher");
  EXPECT_EQ(arg(steps[1], "VocabTreeMatching.vocab_tree_path"), "ws/sfm/vocab_tree.bin");
  // The photo itself is the first retrieved: neighbours + 1.
  EXPECT_EQ(arg(steps[1], "VocabTreeMatching.num_images"), std::to_string(options.vocab_tree_neighbors + 1));
}

TEST(ColmapSteps, SpatialAndSequentialMatching) {
  SfmOptions options;
  PhotoSetFacts with_gps = facts(100, 100, 4000);
  auto steps = matching_steps(context(), plan_sfm(with_gps, options), options);
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_EQ(steps[0].command, "spatial_matcher");
  EXPECT_EQ(arg(steps[0], "SpatialMatching.is_gps"), "1");
  EXPECT_EQ(arg(steps[0], "SpatialMatching.ignore_z"), "0");
  EXPECT_EQ(arg(steps[0], "SpatialMatching.max_num_neighbors"), "20");
  // Some photos without altitude (staged as altitude 0): height ignored.
  with_gps.photos_without_altitude = 3;
  EXPECT_EQ(arg(matching_steps(context(), plan_sfm(with_gps, options), options)[0], "SpatialMatching.ignore_z"), "1");
  options.matcher = "sequential";
  options.sequential_overlap = 7;
  // 100 frames are many overlaps long: loop closures from a vocabulary tree.
  steps = matching_steps(context(), plan_sfm(facts(100, 0, 800), options), options);
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_EQ(steps[0].command, "vocab_tree_builder");
  EXPECT_EQ(steps[1].command, "sequential_matcher");
  EXPECT_EQ(arg(steps[1], "SequentialMatching.overlap"), "7");
  EXPECT_EQ(arg(steps[1], "SequentialMatching.loop_detection"), "1");
  // 10 frames: every pair is within the overlap.
  steps = matching_steps(context(), plan_sfm(facts(10, 0, 800), options), options);
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_EQ(arg(steps[0], "SequentialMatching.overlap"), "7");
  SfmPlan bad;
  bad.matcher = "nearest";
  EXPECT_THROW(matching_steps(context(), bad, options), ConfigError);
}

TEST(ColmapSteps, MapperAdjustsOnBothCoresAndLessOften) {
  SfmOptions options;
  options.ba_global_ratio = 1.3;
  options.min_pose_inliers = 17;
  const ColmapStep step = mapping_step(context(), options);
  EXPECT_EQ(step.command, "mapper");
  EXPECT_EQ(arg(step, "Mapper.num_threads"), "-1");
  EXPECT_EQ(arg(step, "Mapper.ba_min_num_residuals_for_multi_threading"), "1000");
  EXPECT_EQ(arg(step, "Mapper.ba_global_images_ratio"), "1.3");
  EXPECT_EQ(arg(step, "Mapper.ba_global_points_ratio"), "1.3");
  EXPECT_EQ(arg(step, "Mapper.abs_pose_min_num_inliers"), "17");
  EXPECT_EQ(arg(step, "output_path"), "ws/sfm/sparse");
}

TEST(ColmapSteps, PrincipalPointStepAdjustsTheMappedModelIntoAnotherFolder) {
  const ColmapStep step = principal_point_step("ws/sfm/sparse/0", "ws/sfm/sparse/principal_point", true);
  EXPECT_EQ(step.command, "bundle_adjuster");
  EXPECT_EQ(arg(step, "input_path"), "ws/sfm/sparse/0");
  EXPECT_EQ(arg(step, "output_path"), "ws/sfm/sparse/principal_point");
  EXPECT_EQ(arg(step, "BundleAdjustment.refine_principal_point"), "1");
  EXPECT_EQ(arg(step, "BundleAdjustment.refine_focal_length"), "1");
  // The second adjustment, around principal points that were reset.
  EXPECT_EQ(arg(principal_point_step("a", "b", false), "BundleAdjustment.refine_principal_point"), "0");
}

}  // namespace
}  // namespace hos::sfm
