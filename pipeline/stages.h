// The pipeline's stages in order: the one table of what each stage is
// called, which executable runs it, what it reads and writes, its options,
// how it splits, what it costs (disk, memory, time), its key figures and its
// report plots. Everything else (config sections, the run record,
// --from/--to, the Slurm jobs, the summary, the run report) derives from it.
// Each stage's entry is in its own file (pipeline/<stage>_stage.cpp).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/driver_options.h"
#include "pipeline/file_hash.h"
#include "pipeline/pipeline_config.h"
#include "pipeline/run_bounds.h"
#include "pipeline/stage_config.h"
#include "pipeline/stage_paths.h"
#include "pipeline/stage_plot.h"

namespace hos::pipeline {

// A stage whose work can run as parallel parts (a job array on a cluster),
// then one step that joins the parts: chunks of the views (mvs, texture), or
// the tiles of a tiled reconstruction (recon).
struct StageSplit {
  std::string part_name;  // "depth": the parts are the jobs "mvs-depth"
  std::string join_name;  // "fuse"
  // Arguments of one part: `part` is the views "FIRST-LAST" it computes, or
  // with fixed_parts its index.
  std::function<std::vector<std::string>(const StagePaths&, const std::string& part)> part_arguments;
  // Arguments of the join, which writes the stage's result.
  std::function<std::vector<std::string>(const StagePaths&)> join_arguments;
  // Set when the stage's own options fix the parts (recon: one per tile of
  // recon.tiles): their number, below 2 when the stage runs whole. Unset:
  // the views are chunked into as many parts as the executor asks for.
  std::function<int(const PipelineConfig&)> fixed_parts;
  // Without fixed_parts: the --executor-option key that sets the number of
  // parts ("mvs_tasks") and what the parts compute, for its documentation
  // ("depth maps": "array tasks of the mvs depth maps").
  std::string tasks_option;
  std::string parts_text;
};

// Which of a stage's cluster jobs an estimate is for: the stage as one job,
// one part of a stage that splits, or the join of its parts.
enum class StageJob { kWhole, kPart, kJoin };

struct StageSpec {
  std::string name;  // also its YAML section and its workspace folder
  std::string executable;
  // Arguments naming the stage's inputs and outputs.
  std::function<std::vector<std::string>(const DriverOptions&, const StagePaths&)> arguments;
  // Adds the stage's input files to the fingerprint.
  std::function<void(Fingerprint&, const DriverOptions&, const PipelineConfig&, const StagePaths&)> inputs;
  // The stage's result exists (a stage writes it last, atomically).
  std::function<bool(const StagePaths&)> output_exists;
  // A fresh config with the stage's defaults; nullptr when the stage's
  // library is not part of this build.
  std::function<std::unique_ptr<StageConfig>()> make_config;
  // Set for a stage that splits (executors that run parts in parallel use it).
  std::optional<StageSplit> split;

  // Rough bytes the stage adds to the workspace (its outputs and scratch
  // files), from the sizes of its inputs: only for an early warning.
  std::function<std::uintmax_t(const std::filesystem::path& photos, const StagePaths&)> disk_bytes;
  // The memory a cluster job asks for, in MB, from the stage's own bounds
  // (0: no estimate of its own, the executor's default).
  std::function<int(StageJob, const PipelineConfig&, int views)> job_memory_mb;
  // The CPU seconds a cluster job needs by the stage's own estimate (its
  // wall time on one core; docs/scale.md); chunk_views is a part's share of
  // the views, between 1 and bounds.views. 0 when it cannot be told before
  // the run.
  std::function<double(StageJob, const PipelineConfig&, const RunBounds&, double chunk_views)> job_cpu_seconds;
  // Adds the key figures of the stage's outputs to figures (for run.json and
  // the summary); may throw once some are added (the rest are left out).
  std::function<void(const StagePaths&, nlohmann::ordered_json& figures)> read_figures;
  // Those figures as one line, e.g. "16/16 images registered, 4210 points".
  std::function<std::string(const nlohmann::ordered_json& figures)> figures_text;
  // The run report's plots of the stage, each only where its data is in the
  // workspace; may throw InputError on a damaged report file.
  std::function<std::vector<StagePlot>(const StagePaths&)> plots;
};

const std::vector<StageSpec>& pipeline_stages();

// The stage called name, or null.
const StageSpec* find_stage(const std::string& name);

// The stage and the job of a cluster job's name ("mvs-depth": mvs, kPart);
// false for a name no stage has.
bool find_stage_job(const std::string& job, const StageSpec*& spec, StageJob& kind);

// Index of the stage called name; ConfigError naming flag and the stages otherwise.
std::size_t stage_index(const std::string& name, const std::string& flag);

// "sfm, mvs, recon, refine, texture" with the given separator.
std::string stage_names_text(const std::string& separator);

}  // namespace hos::pipeline
