#include "sfm/colmap_steps.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "core/error.h"

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

TEST(ColmapSteps, ExtractionIsBoundedAndUsesEveryCore) {
  const SfmOptions options;
  const SfmPlan plan = plan_sfm({11, 0, 3072}, options);
  const ColmapStep step = feature_extraction_step(context(), plan, options);
  EXPECT_EQ(step.command, "feature_extractor");
  EXPECT_EQ(arg(step, "SiftExtraction.max_image_size"), "2400");
  EXPECT_EQ(arg(step, "SiftExtraction.first_octave"), "0");
  EXPECT_EQ(arg(step, "SiftExtraction.max_num_features"), "4096");
  EXPECT_EQ(arg(step, "SiftExtraction.num_threads"), "-1");
  EXPECT_EQ(arg(step, "SiftExtraction.use_gpu"), "0");
  // Small photos keep COLMAP's upsampled first octave.
  EXPECT_EQ(
      arg(feature_extraction_step(context(), plan_sfm({36, 0, 800}, options), options), "SiftExtraction.first_octave"),
      "-1");
}

TEST(ColmapSteps, ExhaustiveMatchingIsOneCommandWithTheMatchCap) {
  const SfmOptions options;
  const auto steps = matching_steps(context(), plan_sfm({11, 0, 3072}, options), options);
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_EQ(steps[0].command, "exhaustive_matcher");
  EXPECT_EQ(arg(steps[0], "SiftMatching.max_num_matches"), "2048");
  EXPECT_EQ(arg(steps[0], "SiftMatching.num_threads"), "-1");
  EXPECT_EQ(steps[0].total, 4);  // 100 images in blocks of 50: 2 x 2 blocks
}

TEST(ColmapSteps, VocabularyTreeIsBuiltFromThePhotosFirst) {
  const SfmOptions options;
  const SfmPlan plan = plan_sfm({100, 0, 800}, options);
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
  auto steps = matching_steps(context(), plan_sfm({100, 100, 4000}, options), options);
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_EQ(steps[0].command, "spatial_matcher");
  EXPECT_EQ(arg(steps[0], "SpatialMatching.is_gps"), "1");
  EXPECT_EQ(arg(steps[0], "SpatialMatching.max_num_neighbors"), "20");
  options.matcher = "sequential";
  options.sequential_overlap = 7;
  steps = matching_steps(context(), plan_sfm({100, 0, 800}, options), options);
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_EQ(steps[0].command, "sequential_matcher");
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
  const ColmapStep step = principal_point_step("ws/sfm/sparse/0", "ws/sfm/sparse/principal_point");
  EXPECT_EQ(step.command, "bundle_adjuster");
  EXPECT_EQ(arg(step, "input_path"), "ws/sfm/sparse/0");
  EXPECT_EQ(arg(step, "output_path"), "ws/sfm/sparse/principal_point");
  EXPECT_EQ(arg(step, "BundleAdjustment.refine_principal_point"), "1");
  EXPECT_EQ(arg(step, "BundleAdjustment.refine_focal_length"), "1");
}

}  // namespace
}  // namespace hos::sfm
