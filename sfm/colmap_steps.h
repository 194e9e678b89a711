// The COLMAP commands of one sfm run with their arguments: feature
// extraction, matching (one or two commands), mapping. Built from the plan
// (sfm_plan.h) and the options, so tests can check what COLMAP is asked to do.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "sfm/colmap_runner.h"
#include "sfm/sfm_options.h"
#include "sfm/sfm_plan.h"

namespace hos::sfm {

// What every step of one run shares.
struct ColmapRunContext {
  std::filesystem::path database;    // WS/sfm/database.db
  std::filesystem::path images;      // the staged photos
  std::filesystem::path sparse;      // mapper output folder
  std::filesystem::path vocab_tree;  // the tree built from the photos (vocab_tree matcher)
  std::filesystem::path masks;       // the staged masks (NAME.png); empty: no photo has one
  bool gpu = false;                  // SIFT on the GPU
  std::int64_t num_images = 0;
};

// The feature_extractor run over the photos listed in image_list (one
// staged name a line, as image_list_file_text writes them), into the
// shared database; with context.masks, no feature is kept in a masked pixel.
ColmapStep feature_extraction_step(const ColmapRunContext& context,
                                   const ExtractionRun& run,
                                   const std::filesystem::path& image_list,
                                   const SfmPlan& plan,
                                   const SfmOptions& options);

// The text of an image list file for COLMAP: the names relative to the
// image folder (a name may hold '/', for photos from subfolders).
std::string image_list_file_text(const ExtractionRun& run);

// One command, or two for the vocabulary tree (vocab_tree_builder over the
// photos' own features, then vocab_tree_matcher).
std::vector<ColmapStep> matching_steps(const ColmapRunContext& context, const SfmPlan& plan, const SfmOptions& options);

ColmapStep mapping_step(const ColmapRunContext& context, const SfmOptions& options);

// A bundle adjustment of the model in input (focal lengths and distortion
// refined; the principal points too when refine_principal_point), written
// to output.
ColmapStep principal_point_step(const std::filesystem::path& input,
                                const std::filesystem::path& output,
                                bool refine_principal_point);

}  // namespace hos::sfm
