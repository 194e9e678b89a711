// hos-pipeline's library: chains the stage executables (pipeline/stages.h)
// through files in a workspace, skips stages whose inputs and config are
// unchanged since the last run, and records the run. Runs the stages here or
// on Slurm (pipeline/slurm/) and writes the run report (pipeline/report/).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/reporter.h"
#include "pipeline/driver_options.h"
#include "pipeline/run_record.h"

namespace hos::pipeline {

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

// The summary table printed at the end.
std::vector<std::string> summary_table(const DriverResult& result);

}  // namespace hos::pipeline
