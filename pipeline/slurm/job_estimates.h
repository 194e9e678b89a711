// What a cluster job asks for (sbatch --mem and --time), from its stage's
// own estimates in the stage table (pipeline/stages.h: the stages' bounds
// and the measured speeds of docs/benchmarks*.md). Jobs are submitted before
// the stages before them have run, so the estimates start from what is known
// then: the photo folder and the options (pipeline/run_bounds.h).
#pragma once

#include <filesystem>
#include <string>

#include "pipeline/pipeline_config.h"
#include "pipeline/run_bounds.h"

namespace hos::pipeline {

// The memory a job ("sfm", "mvs-depth", "recon-join", ...) asks for, in MB:
// its stage's estimate, else default_mb (0: not given).
int job_memory_mb(const std::string& job, const PipelineConfig& config, int views, int default_mb);

// The CPU seconds a job (sfm, mvs-depth, mvs-fuse, recon, recon-tiles,
// recon-join, refine, texture-views, texture-atlas) needs by its stage's own
// estimate, i.e. its wall time on one core; chunk_views is an array task's
// share of the views. 0 when the stage cannot estimate it from what is known
// before the run, or no stage has such a job. docs/scale.md gives the model
// and the measured figure of each.
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
