// hos-pipeline's library: chains the stage executables (hos-sfm, hos-mvs,
// hos-recon, hos-texture) through files in a workspace, skips stages whose
// inputs and config are unchanged since the last run, and records the run.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/reporter.h"
#include "pipeline/run_record.h"

namespace hos::pipeline {

struct DriverOptions {
  std::filesystem::path photos;          // folder of photos
  std::filesystem::path output;          // OUT.glb
  std::filesystem::path workspace;       // empty: OUT's folder / "<OUT stem>_workspace"
  std::filesystem::path existing_model;  // optional COLMAP sparse model of the photos (sfm skips SfM)
  std::string preset = "default";        // fast | default | quality | a YAML file
  std::string config_file;               // --config
  std::vector<std::string> assignments;  // --set stage.key=value
  std::string from;                      // first stage to consider (empty: sfm)
  std::string to;                        // last stage (empty: texture)
  bool force = false;                    // run the stages in range even if up to date
  std::string progress = "auto";         // passed to the stages
  bool verbose = false;
  std::filesystem::path bin_dir;              // where the stage executables are
  std::string executor = "local";             // local | slurm (pipeline/slurm_executor.h)
  std::vector<std::string> executor_options;  // --executor-option KEY=VALUE (slurm: partition, account, ...)
};

struct StageOutcome {
  std::string stage;
  std::string state;  // "ran", "up to date", "not run"; on Slurm "done", "submitted", "not run"
  StageRecord record;
};

struct DriverResult {
  std::filesystem::path workspace;
  std::filesystem::path output;  // empty when --to stops before texture
  std::vector<StageOutcome> stages;
};

// The default workspace of an output: OUT's folder / "<OUT stem>_workspace".
std::filesystem::path default_workspace(const std::filesystem::path& output);

// Runs the pipeline. Throws ConfigError (bad option or stage name), InputError
// (missing photos), OutputError (output folder missing), StageError (a stage
// executable missing or failed; its own exit code is kept where it names a
// cause: bad input, bad config, unwritable output), Cancelled.
DriverResult run_pipeline(const DriverOptions& options, Reporter& reporter);

// Throws the error a stage's exit code names (ConfigError for 2, InputError
// for 3 with input_hint, OutputError for 5, Cancelled for 130, StageError
// otherwise), naming its log.
[[noreturn]] void throw_stage_failure(const std::string& stage,
                                      int code,
                                      const std::filesystem::path& log,
                                      const std::string& input_hint);

// The summary table printed at the end.
std::vector<std::string> summary_table(const DriverResult& result);

}  // namespace hos::pipeline
