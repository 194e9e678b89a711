#include "sfm/colmap_steps.h"

#include "core/error.h"

namespace hos::sfm {
namespace {

constexpr int kExhaustiveBlockSize = 50;  // COLMAP's default block size
// k-means branching of the vocabulary tree: with COLMAP's 256 every
// descriptor is compared with 256 centres at the first level. On the features
// of 36 photos, 512 words took 4 CPU s with 16 against 15 with 256.
constexpr int kVocabTreeBranching = 16;
// Bundle adjustment runs single-threaded below this many residuals (COLMAP's
// default 50000 keeps every adjustment of a 10-photo set on one core).
constexpr int kBaMultiThreadingResiduals = 1000;
// Small secondary models are kept so that a split can be reported.
constexpr int kMinModelSize = 3;

std::string flag(bool value) { return value ? "1" : "0"; }

// Arguments every command takes: seed and database.
std::vector<std::string> common_args(const ColmapRunContext& context, const SfmOptions& options) {
  return {"--random_seed", std::to_string(options.random_seed), "--database_path", context.database.string()};
}

std::vector<std::string> sift_matching_args(const ColmapRunContext& context,
                                            const SfmPlan& plan,
                                            const SfmOptions& options) {
  std::vector<std::string> args = common_args(context, options);
  args.insert(args.end(), {"--SiftMatching.use_gpu", flag(context.gpu), "--SiftMatching.num_threads",
                           std::to_string(options.num_threads), "--SiftMatching.max_num_matches",
                           std::to_string(plan.max_num_matches)});
  return args;
}

}  // namespace

ColmapStep feature_extraction_step(const ColmapRunContext& context,
                                   const ExtractionRun& run,
                                   const std::filesystem::path& image_list,
                                   const SfmPlan& plan,
                                   const SfmOptions& options) {
  ColmapStep step{"feature_extractor", common_args(context, options), "extracting features",
                  static_cast<std::int64_t>(run.names.size())};
  step.args.insert(step.args.end(), {"--image_path",
                                     context.images.string(),
                                     "--image_list_path",
                                     image_list.string(),
                                     "--ImageReader.camera_model",
                                     options.camera_model,
                                     "--ImageReader.single_camera",
                                     flag(run.single_camera),
                                     "--SiftExtraction.use_gpu",
                                     flag(context.gpu),
                                     "--SiftExtraction.num_threads",
                                     std::to_string(options.num_threads),
                                     "--SiftExtraction.max_image_size",
                                     std::to_string(run.sift_max_image_size),
                                     "--SiftExtraction.first_octave",
                                     run.sift_upsample ? "-1" : "0",
                                     "--SiftExtraction.max_num_features",
                                     std::to_string(plan.max_num_features),
                                     "--SiftExtraction.peak_threshold",
                                     format_message(options.sift_peak_threshold)});
  if (!context.masks.empty()) step.args.insert(step.args.end(), {"--ImageReader.mask_path", context.masks.string()});
  return step;
}

std::string image_list_file_text(const ExtractionRun& run) {
  std::string text;
  for (const std::string& name : run.names) text += name + "\n";
  return text;
}

namespace {

// The tree is learnt from these photos' own descriptors: nothing is
// downloaded, and its words fit the scene.
ColmapStep vocab_tree_builder_step(const ColmapRunContext& context, const SfmPlan& plan, const SfmOptions& options) {
  return {"vocab_tree_builder",
          {"--random_seed", std::to_string(options.random_seed), "--database_path", context.database.string(),
           "--vocab_tree_path", context.vocab_tree.string(), "--num_visual_words",
           std::to_string(plan.vocab_tree_words), "--branching", std::to_string(kVocabTreeBranching)},
          "building the vocabulary tree",
          0};
}

}  // namespace

std::vector<ColmapStep> matching_steps(const ColmapRunContext& context,
                                       const SfmPlan& plan,
                                       const SfmOptions& options) {
  ColmapStep match{plan.matcher + "_matcher", sift_matching_args(context, plan, options),
                   "matching (" + plan.matcher + ")", context.num_images};
  std::vector<ColmapStep> steps;
  if (plan.matcher == "exhaustive") {
    const std::int64_t blocks = (context.num_images + kExhaustiveBlockSize - 1) / kExhaustiveBlockSize;
    match.args.insert(match.args.end(), {"--ExhaustiveMatching.block_size", std::to_string(kExhaustiveBlockSize)});
    match.total = blocks * blocks;
  } else if (plan.matcher == "sequential") {
    match.args.insert(match.args.end(), {"--SequentialMatching.overlap", std::to_string(options.sequential_overlap)});
    if (plan.loop_detection) {
      // Every loop_detection_period-th frame retrieves similar frames from
      // the whole set: a clip coming back to its start closes the loop.
      steps.push_back(vocab_tree_builder_step(context, plan, options));
      match.args.insert(match.args.end(),
                        {"--SequentialMatching.loop_detection", "1", "--SequentialMatching.vocab_tree_path",
                         context.vocab_tree.string(), "--SequentialMatching.loop_detection_num_images",
                         std::to_string(options.vocab_tree_neighbors)});
    }
  } else if (plan.matcher == "spatial") {
    // Without altitude (staged as 0) only latitude and longitude count.
    match.args.insert(match.args.end(),
                      {"--SpatialMatching.is_gps", "1", "--SpatialMatching.ignore_z", flag(plan.spatial_ignore_z),
                       "--SpatialMatching.max_num_neighbors", std::to_string(options.spatial_neighbors)});
  } else if (plan.matcher == "vocab_tree") {
    steps.push_back(vocab_tree_builder_step(context, plan, options));
    match.args.insert(match.args.end(),
                      {"--VocabTreeMatching.vocab_tree_path", context.vocab_tree.string(),
                       "--VocabTreeMatching.num_images", std::to_string(options.vocab_tree_neighbors + 1)});
  } else {
    throw ConfigError("sfm.matcher", "unknown matcher '" + plan.matcher + "'");
  }
  steps.push_back(std::move(match));
  return steps;
}

ColmapStep mapping_step(const ColmapRunContext& context, const SfmOptions& options) {
  const std::string ba_ratio = format_message(options.ba_global_ratio);
  ColmapStep step{"mapper", common_args(context, options), "mapping", context.num_images};
  step.args.insert(
      step.args.end(),
      {"--image_path", context.images.string(), "--output_path", context.sparse.string(), "--Mapper.num_threads",
       std::to_string(options.num_threads), "--Mapper.min_model_size", std::to_string(kMinModelSize),
       "--Mapper.abs_pose_min_num_inliers", std::to_string(options.min_pose_inliers),
       "--Mapper.ba_min_num_residuals_for_multi_threading", std::to_string(kBaMultiThreadingResiduals),
       "--Mapper.ba_global_images_ratio", ba_ratio, "--Mapper.ba_global_points_ratio", ba_ratio});
  return step;
}

ColmapStep principal_point_step(const std::filesystem::path& input,
                                const std::filesystem::path& output,
                                bool refine_principal_point) {
  return {"bundle_adjuster",
          {"--input_path", input.string(), "--output_path", output.string(),
           "--BundleAdjustment.refine_principal_point", flag(refine_principal_point),
           "--BundleAdjustment.refine_focal_length", "1", "--BundleAdjustment.refine_extra_params", "1"},
          "adjusting the principal point",
          0};
}

}  // namespace hos::sfm
