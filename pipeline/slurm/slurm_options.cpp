#include "pipeline/slurm/slurm_options.h"

#include "core/error.h"
#include "core/option_set.h"
#include "pipeline/stages.h"

namespace hos::pipeline {

int SlurmOptions::tasks_of(const std::string& stage) const {
  const auto it = tasks.find(stage);
  if (it != tasks.end()) return it->second;
  const StageSpec* spec = find_stage(stage);
  if (spec && spec->split && !spec->split->tasks_option.empty()) return kDefaultArrayTasks;
  throw ConfigError("--executor-option " + stage + "_tasks", "the stage " + stage + " does not split");
}

void register_options(OptionSet& set, SlurmOptions& o) {
  set.add("partition", o.partition, "sbatch --partition (empty: the cluster's default)");
  set.add("account", o.account, "sbatch --account (empty: the cluster's default)");
  set.add("qos", o.qos, "sbatch --qos (empty: the cluster's default)");
  set.add("constraint", o.constraint, "sbatch --constraint (empty: none)");
  set.add("time", o.time, "sbatch --time of every job (empty: each job's own estimate)");
  set.add("mem_mb", o.mem_mb, "sbatch --mem of jobs without an estimate of their own (0: not given)", 0, 1 << 30);
  set.add("cpus", o.cpus, "sbatch --cpus-per-task (0: not given)", 0, 65536);
  // A key per stage that splits into chunks of the views (the stage table's tasks_option).
  for (const StageSpec& spec : pipeline_stages()) {
    if (!spec.split || spec.split->tasks_option.empty()) continue;
    int& tasks = o.tasks.try_emplace(spec.name, kDefaultArrayTasks).first->second;
    set.add(spec.split->tasks_option, tasks, "array tasks of the " + spec.name + " " + spec.split->parts_text, 1,
            100000);
  }
  set.add("poll_seconds", o.poll_seconds, "seconds between squeue queries while waiting", 0.0, 3600.0);
  set.add("status_grace_seconds", o.status_grace_seconds,
          "seconds a job that left the queue may lack its status file before it counts as failed", 0.0, 86400.0);
  set.add("wait", o.wait, "wait for the jobs (false: submit and return)");
}

SlurmOptions parse_slurm_options(const std::vector<std::string>& items) {
  SlurmOptions o;
  OptionSet set("slurm");
  register_options(set, o);
  for (const std::string& item : items) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) throw ConfigError("--executor-option " + item, "expected KEY=VALUE");
    const std::string key = item.substr(0, eq);
    if (!set.has_key(key)) {
      std::string keys;
      for (const std::string& k : set.keys()) keys += (keys.empty() ? "" : ", ") + k;
      throw ConfigError("--executor-option " + item,
                        "unknown key; did you mean " + set.closest_key(key) + "? The keys are " + keys);
    }
    set.apply_assignment(key, item.substr(eq + 1), "--executor-option");
  }
  return o;
}

}  // namespace hos::pipeline
