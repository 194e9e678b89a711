// The pipeline's stages in order: the one list of what each stage is called,
// which executable runs it, what it reads and writes, and its options.
// Everything else (config sections, the run record, --from/--to, messages)
// derives from it.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/driver_options.h"
#include "pipeline/file_hash.h"
#include "pipeline/pipeline_config.h"
#include "pipeline/stage_config.h"
#include "pipeline/stage_paths.h"

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
};

struct StageSpec {
  std::string name;  // also its YAML section and its workspace folder
  std::string executable;
  // Arguments naming the stage's inputs and outputs.
  std::function<std::vector<std::string>(const DriverOptions&, const StagePaths&)> arguments;
  // Adds the stage's input files to the fingerprint.
  std::function<void(Fingerprint&, const DriverOptions&, const StagePaths&)> inputs;
  // The stage's result exists (a stage writes it last, atomically).
  std::function<bool(const StagePaths&)> output_exists;
  // A fresh config with the stage's defaults; nullptr when the stage's
  // library is not part of this build.
  std::function<std::unique_ptr<StageConfig>()> make_config;
  // Set for a stage that splits (executors that run parts in parallel use it).
  std::optional<StageSplit> split;
};

const std::vector<StageSpec>& pipeline_stages();

// Index of the stage called name; ConfigError naming flag and the stages otherwise.
std::size_t stage_index(const std::string& name, const std::string& flag);

// "sfm, mvs, recon, texture" with the given separator.
std::string stage_names_text(const std::string& separator);

}  // namespace hos::pipeline
