// What is known of a run's input before any stage has run: the stages'
// time and memory estimates (pipeline/stages.h) start from it, since cluster
// jobs are submitted before the stages before them have run.
#pragma once

#include <filesystem>

#include "pipeline/pipeline_config.h"

namespace hos::pipeline {

struct RunBounds {
  int views = 1;                  // files in the photo folder: sfm registers at most these
  double photo_megapixels = 0.0;  // of the largest photo, as the stages after sfm see it (0: unknown)
};

// The bounds of the photos in folder: the number of files (hidden ones
// skipped), and the size of the largest file decoded at 1/8 scale (cheap
// for JPEG), capped by sfm.max_image_size when that is set.
RunBounds run_bounds(const std::filesystem::path& photos, const PipelineConfig& config);

// Megapixels of a 4:3 image whose longest side is size.
double megapixels_at(int size);

}  // namespace hos::pipeline
