// The Slurm jobs of a run: which jobs the stages become (a stage that splits
// becomes an array of parts and a join), each job's script, and the status
// file the script leaves (WS/slurm/status/<job>[.<task>].exit: exit code,
// wall seconds, user and system time).
#pragma once

#include <cstddef>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "pipeline/driver_options.h"
#include "pipeline/pipeline_config.h"
#include "pipeline/slurm/job_estimates.h"
#include "pipeline/slurm/slurm_options.h"
#include "pipeline/stage_paths.h"
#include "pipeline/stages.h"

namespace hos::pipeline {

// One sbatch submission: a stage, or one part of a stage that splits.
struct Job {
  std::string name;  // "sfm", "mvs-depth", "mvs-fuse", ...: the status file, log and record key
  std::size_t stage = 0;
  std::vector<std::string> argv;
  std::filesystem::path log;
  int tasks = 0;  // job array size; 0: a single job
  int chunk = 0;  // views per array task; 0: a task is its index (a tile)
};

// The jobs of the stages first..last of pipeline_stages(), in order.
std::vector<Job> plan_jobs(const DriverOptions& driver,
                           const SlurmOptions& options,
                           std::size_t first,
                           std::size_t last,
                           const StagePaths& paths,
                           const PipelineConfig& config,
                           const RunBounds& bounds);

// The job names of a stage that splits ("mvs-depth", "mvs-fuse").
std::string part_job_name(const StageSpec& spec);
std::string join_job_name(const StageSpec& spec);

// The job script: #SBATCH lines for what does not change between
// submissions; the dependency and the array's task list go on sbatch's
// command line.
std::string job_script(const Job& job,
                       const SlurmOptions& options,
                       const PipelineConfig& config,
                       const RunBounds& bounds,
                       const StagePaths& paths);

// The status file of a job's task (task 0 for a single job) and its log.
std::filesystem::path status_file(const StagePaths& paths, const Job& job, int task);
std::filesystem::path task_log(const Job& job, int task);

enum class TaskState { kActive, kCompleted, kFailed };

struct TaskStatus {
  TaskState state = TaskState::kFailed;
  int exit_code = 0;
  std::string reason;
  double seconds = 0;      // the job's wall time, from its status file
  double cpu_seconds = 0;  // its user + system time, from its status file (0: not there)
};

// How the task whose Slurm id is id stands: active when squeue lists it
// (active), else as its status file says; without one, failed with sacct's
// reason.
TaskStatus task_status(const std::string& id, const std::filesystem::path& status, const std::set<std::string>& active);

}  // namespace hos::pipeline
