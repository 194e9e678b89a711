// What a cluster job asks for (sbatch --mem and --time), from the stages'
// own bounds and the measured speeds of docs/benchmarks*.md. Jobs are
// submitted before the stages before them have run, so the estimates start
// from what is known then: the photo folder and the options.
#pragma once

#include <filesystem>
#include <string>

#include "pipeline/pipeline_config.h"

namespace hos::pipeline {

// What is known of a run's input before any stage has run.
struct RunBounds {
  int views = 1;                  // files in the photo folder: sfm registers at most these
  double photo_megapixels = 0.0;  // of the largest photo, as the stages after sfm see it (0: unknown)
};

// The bounds of the photos in folder: the number of files (hidden ones
// skipped), and the size of the largest file decoded at 1/8 scale (cheap
// for JPEG), capped by sfm.max_image_size when that is set.
RunBounds run_bounds(const std::filesystem::path& photos, const PipelineConfig& config);

// The memory a job asks for, in MB (0: not given): mvs depth chunks and
// fusion from the image size the options allow, recon (also each tile task
// and the join of a tiled recon) from its own memory budget
// (recon.max_memory_mb) when one is set, the others default_mb.
int job_memory_mb(const std::string& job, const PipelineConfig& config, int views, int default_mb);

// The CPU seconds a job (sfm, mvs-depth, mvs-fuse, recon, recon-tiles,
// recon-join, refine, texture-views, texture-atlas) needs by its stage's own estimate, i.e. its
// wall time on one core; chunk_views is an array task's share of the views.
// 0 when the stage cannot estimate it from what is known before the run.
// docs/scale.md gives the model and the measured figure of each.
double job_cpu_seconds(const std::string& job, const PipelineConfig& config, const RunBounds& bounds, int chunk_views);

// The job's sbatch --time: time_option when given, else the estimate times
// kTimeSafetyFactor, at least kMinTimeSeconds; "" when there is neither.
inline constexpr double kTimeSafetyFactor = 2.0;
inline constexpr double kMinTimeSeconds = 600.0;
std::string job_time_limit(const std::string& job,
                           const PipelineConfig& config,
                           const RunBounds& bounds,
                           int chunk_views,
                           const std::string& time_option);

// seconds rounded up to whole minutes, as sbatch --time takes them:
// "HH:MM:SS" below a day, "D-HH:MM:SS" from a day on.
std::string slurm_time_text(double seconds);

}  // namespace hos::pipeline
