// Slurm's client commands as hos-pipeline runs them: sbatch to submit,
// squeue for what is still queued or running, sacct for why a job ended,
// scancel to cancel.
#pragma once

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "core/reporter.h"

namespace hos::pipeline {

struct CommandOutput {
  int exit_code = 0;
  std::string text;  // stdout and stderr, line by line
};

// Runs a command and collects its output.
CommandOutput run_command(const std::vector<std::string>& argv);

// s without leading and trailing white space.
std::string trimmed(const std::string& s);

// sbatch --parsable of script: with array_tasks as --array when array is
// set, after the jobs `after` (--dependency=afterok). The command's output.
CommandOutput run_sbatch(const std::filesystem::path& script,
                         bool array,
                         const std::vector<int>& array_tasks,
                         const std::vector<std::string>& after);

// The job ids squeue lists as pending, running or about to end, one per
// array task. Throws StageError when squeue fails.
std::set<std::string> active_job_ids();

// Why a job without a status file ended, from sacct when the cluster keeps
// accounting ("CANCELLED", "OUT_OF_MEMORY", "TIMEOUT", "NODE_FAIL"); "" when
// it does not say.
std::string sacct_state(const std::string& id);

// scancel of ids (nothing when empty); a failure is a warning.
void cancel_jobs(const std::vector<std::string>& ids, Reporter& reporter);

}  // namespace hos::pipeline
