// The Slurm executor's options (--executor-option KEY=VALUE): sbatch's
// resources and how many array tasks a stage that splits runs as.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace hos {
class OptionSet;
}

namespace hos::pipeline {

inline constexpr int kDefaultArrayTasks = 4;

// --executor-option KEY=VALUE.
struct SlurmOptions {
  std::string partition;   // sbatch --partition (empty: the cluster's default)
  std::string account;     // sbatch --account
  std::string qos;         // sbatch --qos
  std::string constraint;  // sbatch --constraint
  std::string time;        // sbatch --time of every job (empty: each job's own estimate, job_estimates.h)
  int mem_mb = 0;          // sbatch --mem of jobs without an estimate of their own (0: not given)
  int cpus = 0;            // sbatch --cpus-per-task (0: not given)
  // Array tasks per stage that splits into chunks of the views, by stage
  // name; the keys are the stage table's tasks_option ("mvs_tasks").
  std::map<std::string, int> tasks;
  double poll_seconds = 10;  // between squeue queries while waiting
  // A job squeue no longer lists whose status file is not (yet) visible
  // counts as failed after this long: a shared filesystem may show a file
  // written on a compute node later on the login node.
  double status_grace_seconds = 30;
  bool wait = true;  // wait for the jobs (Ctrl-C cancels them); false: submit and return

  // The array tasks of a stage that splits into chunks of the views
  // (kDefaultArrayTasks unless set); ConfigError for another stage.
  int tasks_of(const std::string& stage) const;
};

// The keys --executor-option takes (section "slurm"), with their ranges and
// documentation.
void register_options(OptionSet& set, SlurmOptions& o);

// Parses KEY=VALUE items through that table; ConfigError naming an unknown
// key (and the known ones) or a bad value and the allowed ones.
SlurmOptions parse_slurm_options(const std::vector<std::string>& items);

}  // namespace hos::pipeline
