#include "pipeline/slurm/slurm_executor.h"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/subprocess.h"
#include "pipeline/file_hash.h"
#include "pipeline/slurm/slurm_commands.h"
#include "pipeline/slurm/slurm_jobs.h"
#include "pipeline/stage_failure.h"
#include "pipeline/stage_figures.h"
#include "pipeline/stages.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

// The recorded task ids of a job ("0" -> "13_0"), from run.json.
std::map<int, std::string> recorded_tasks(const nlohmann::ordered_json& entry) {
  std::map<int, std::string> tasks;
  if (!entry.is_object() || !entry.contains("tasks")) return tasks;
  for (const auto& [task, id] : entry.at("tasks").items()) tasks[std::stoi(task)] = id.get<std::string>();
  return tasks;
}

// " tasks 0,2" for an array job's tasks, "" for a single job.
std::string tasks_text(const Job& job, const std::vector<int>& tasks) {
  std::string list;
  for (int t : tasks) list += (list.empty() ? " tasks " : ",") + std::to_string(t);
  return job.tasks > 0 ? list : "";
}

// What becomes of a job's tasks when its stage is submitted: the tasks to
// submit (again), the active ones to keep waiting for, the active ones of a
// changed config to cancel.
struct TaskPlan {
  std::vector<int> submit;
  std::vector<std::string> keep, stale;
};

// One run of the Slurm executor: submits what the run record does not show
// as done, pending or running, then waits for it. The record's "slurm"
// entry holds every job's task ids, so a later run resumes.
class SlurmRun {
 public:
  SlurmRun(const DriverOptions& driver,
           const SlurmOptions& options,
           std::size_t first,
           std::size_t last,
           const StagePaths& paths,
           const PipelineConfig& config,
           RunRecord& record,
           Reporter& reporter)
      : driver_(driver),
        options_(options),
        first_(first),
        last_(last),
        paths_(paths),
        config_(config),
        record_(record),
        reporter_(reporter),
        bounds_(run_bounds(driver.photos, config)),
        jobs_(plan_jobs(driver, options, first, last, paths, config, bounds_)) {
    if (!record_.slurm.is_object()) record_.slurm = nlohmann::ordered_json::object();
    if (!record_.slurm.contains("jobs")) record_.slurm["jobs"] = nlohmann::ordered_json::object();
  }

  bool run() {
    try {
      submit();
      if (!options_.wait) {
        reporter_.info("submitted; run the same command again to follow the jobs or resume");
        return false;
      }
      return wait();
    } catch (const Cancelled&) {
      cancel_jobs(active_ids(active_job_ids()), reporter_);
      save();
      reporter_.error("interrupted: the run's Slurm jobs are cancelled; re-run the same command to resume");
      throw;
    }
  }

 private:
  nlohmann::ordered_json& entry(const Job& job) { return record_.slurm["jobs"][job.name]; }
  void save() { save_run_record(record_, paths_.run_record); }
  const StageSpec& spec_of(std::size_t stage) const { return pipeline_stages()[stage]; }

  std::string config_hash(std::size_t stage) const {
    Fingerprint f;
    f.add(config_.section_yaml(spec_of(stage).name));
    return f.hex();
  }
  std::string input_hash(std::size_t stage) const {
    Fingerprint f;
    spec_of(stage).inputs(f, driver_, config_, paths_);
    return f.hex();
  }

  static int task_count(const Job& job) { return std::max(job.tasks, 1); }

  // The active jobs among jobs_[from..].
  std::vector<std::string> active_ids(const std::set<std::string>& active, std::size_t from = 0) {
    std::vector<std::string> ids;
    for (std::size_t j = from; j < jobs_.size(); ++j) {
      for (const auto& [task, id] : recorded_tasks(entry(jobs_[j]))) {
        if (active.count(id)) ids.push_back(id);
      }
    }
    return ids;
  }

  // A stage whose result is current, as the local driver decides it.
  bool up_to_date(std::size_t stage) {
    const StageSpec& spec = spec_of(stage);
    const auto it = record_.stages.find(spec.name);
    if (it == record_.stages.end() || it->second.state != "done") return false;
    return it->second.config_hash == config_hash(stage) && spec.output_exists(paths_) &&
           it->second.input_hash == input_hash(stage);
  }

  // Wall time: the stage's jobs one after the other, an array's tasks side
  // by side (the longest counts); CPU time: every task's. Peak memory needs
  // the cluster's accounting, which hos does not rely on: not recorded.
  void record_times(std::size_t stage, StageRecord& r) {
    r.wall_seconds = 0;
    r.cpu_seconds = 0;
    r.peak_memory_bytes = 0;
    for (const Job& job : jobs_) {
      if (job.stage != stage) continue;
      double longest = 0;
      for (const auto& [t, id] : recorded_tasks(entry(job))) {
        const TaskStatus status = task_status(id, status_file(paths_, job, t), {});
        longest = std::max(longest, status.seconds);
        r.cpu_seconds += status.cpu_seconds;
      }
      r.wall_seconds += longest;
    }
  }

  // Records the stage as done, with figures and fingerprints as a local run
  // would.
  void mark_done(std::size_t stage) {
    const StageSpec& spec = spec_of(stage);
    StageRecord& r = record_.stages[spec.name];
    r.state = "done";
    r.config_hash = config_hash(stage);
    r.input_hash = input_hash(stage);
    r.exit_code = 0;
    r.finished_at = utc_timestamp();
    r.figures = stage_figures(spec.name, paths_.root);
    record_times(stage, r);
    save();
    reporter_.info(spec.name + ": done");
  }

  void mark_submitted(std::size_t stage) {
    StageRecord& r = record_.stages[spec_of(stage).name];
    r = StageRecord{};
    r.state = "submitted";
    r.config_hash = config_hash(stage);
    save();
  }

  // Writes the job's script and submits the tasks after the jobs `after`;
  // returns the Slurm job id.
  std::string submit_job(const Job& job, const std::vector<int>& tasks, const std::vector<std::string>& after) {
    const fs::path script = paths_.root / "slurm" / (job.name + ".sh");
    std::error_code ec;
    fs::create_directories(paths_.root / "slurm" / "status", ec);
    write_atomically(script, [&](const fs::path& tmp) {
      std::ofstream out(tmp);
      out << job_script(job, options_, config_, bounds_, paths_);
      if (!out) throw OutputError(script.string(), "the job script");
    });
    for (int t : tasks) fs::remove(status_file(paths_, job, t), ec);
    const CommandOutput out = run_sbatch(script, job.tasks > 0, tasks, after);
    std::string id = trimmed(out.text.substr(0, out.text.find_first_of(";\n")));
    if (out.exit_code != 0 || id.empty() || id.find_first_not_of("0123456789") != std::string::npos) {
      throw StageError(spec_of(job.stage).name, "sbatch failed for " + job.name + ": " + trimmed(out.text));
    }
    reporter_.info("submitted " + job.name + " as Slurm job " + id + tasks_text(job, tasks));
    return id;
  }

  // The recorded jobs of a stage that the plan no longer has (recon.tiles
  // changed between one job and an array): their active tasks are cancelled
  // and their entries dropped, so that nothing of them runs on.
  void drop_unplanned_jobs(std::size_t stage, const std::set<std::string>& active) {
    const StageSpec& spec = spec_of(stage);
    std::vector<std::string> names{spec.name};
    if (spec.split) names.insert(names.end(), {part_job_name(spec), join_job_name(spec)});
    nlohmann::ordered_json& recorded = record_.slurm["jobs"];
    for (const std::string& name : names) {
      const bool planned = std::any_of(jobs_.begin(), jobs_.end(), [&](const Job& job) { return job.name == name; });
      if (planned || !recorded.contains(name)) continue;
      std::vector<std::string> stale;
      for (const auto& [task, id] : recorded_tasks(recorded[name])) {
        if (active.count(id)) stale.push_back(id);
      }
      cancel_jobs(stale, reporter_);
      recorded.erase(name);
    }
  }

  // With a reusable record (same config, nothing before it submitted again)
  // completed tasks are kept, active ones waited for and failed ones
  // submitted again; otherwise every task is submitted again and the active
  // ones cancelled.
  TaskPlan plan_tasks(const Job& job,
                      const std::map<int, std::string>& recorded,
                      bool reusable,
                      const std::set<std::string>& active) {
    TaskPlan plan;
    for (int t = 0; t < task_count(job); ++t) {
      const auto it = recorded.find(t);
      if (it == recorded.end()) {
        plan.submit.push_back(t);
        continue;
      }
      const TaskStatus status = task_status(it->second, status_file(paths_, job, t), active);
      if (!reusable) {
        if (status.state == TaskState::kActive) plan.stale.push_back(it->second);
        plan.submit.push_back(t);
      } else if (status.state == TaskState::kActive) {
        plan.keep.push_back(it->second);
      } else if (status.state == TaskState::kFailed) {
        reporter_.info(job.name + (job.tasks > 0 ? " task " + std::to_string(t) : "") + " (job " + it->second + ") " +
                       status.reason + "; submitting it again");
        plan.submit.push_back(t);
      }
    }
    return plan;
  }

  // Submits what a job needs and records its tasks; `after` becomes the
  // jobs the next one waits for, `changed` is set once something was
  // submitted. True when the job has nothing left to wait for.
  bool submit_tasks(const Job& job,
                    const std::string& hash,
                    const std::set<std::string>& active,
                    bool& changed,
                    std::vector<std::string>& after) {
    nlohmann::ordered_json& e = entry(job);
    const auto old = recorded_tasks(e);
    const bool reusable = !changed && e.is_object() && e.value("config_hash", "") == hash;
    TaskPlan plan = plan_tasks(job, old, reusable, active);
    cancel_jobs(plan.stale, reporter_);
    nlohmann::ordered_json tasks = nlohmann::ordered_json::object();
    for (const auto& [t, id] : old) {
      if (std::find(plan.submit.begin(), plan.submit.end(), t) == plan.submit.end()) tasks[std::to_string(t)] = id;
    }
    if (!plan.submit.empty()) {
      const std::string id = submit_job(job, plan.submit, after);
      for (int t : plan.submit) tasks[std::to_string(t)] = job.tasks > 0 ? id + "_" + std::to_string(t) : id;
      plan.keep.push_back(id);
      changed = true;
    }
    e = {{"config_hash", hash}, {"array", job.tasks > 0}, {"tasks", tasks}};
    after = plan.keep;
    save();
    return plan.keep.empty();
  }

  // Submits what a stage needs, job by job, then records it as done or
  // submitted.
  void submit_stage(std::size_t stage,
                    const std::set<std::string>& active,
                    bool& changed,
                    std::vector<std::string>& after) {
    drop_unplanned_jobs(stage, active);
    const std::string hash = config_hash(stage);
    bool all_completed = true;
    for (const Job& job : jobs_) {
      if (job.stage == stage && !submit_tasks(job, hash, active, changed, after)) all_completed = false;
    }
    if (all_completed && spec_of(stage).output_exists(paths_)) {
      mark_done(stage);
    } else {
      mark_submitted(stage);
    }
  }

  // Submits what is not done, pending or running, in stage order; what
  // follows a submission is submitted again too (its input will change).
  void submit() {
    const std::set<std::string> active = active_job_ids();
    bool changed = driver_.force;
    std::vector<std::string> after;  // the active or new jobs the next job waits for
    for (std::size_t s = first_; s <= last_; ++s) {
      if (!changed && up_to_date(s)) {
        reporter_.info(spec_of(s).name + ": up to date, skipped");
        continue;
      }
      submit_stage(s, active, changed, after);
    }
  }

  // Looks at a stage's tasks once: true when every one completed and the
  // result is there. A failed task ends the run (fail).
  bool poll_stage(std::size_t stage, const std::set<std::string>& active) {
    bool completed = true;
    for (std::size_t j = 0; j < jobs_.size(); ++j) {
      if (jobs_[j].stage != stage) continue;
      for (const auto& [t, id] : recorded_tasks(entry(jobs_[j]))) {
        const TaskStatus status = task_status(id, status_file(paths_, jobs_[j], t), active);
        if (status.state == TaskState::kActive) completed = false;
        if (status.state != TaskState::kFailed) continue;
        if (status.exit_code < 0 && !grace_over(id)) {
          completed = false;  // no status file yet: look again at the next poll
          continue;
        }
        fail(j, t, id, status, active);
      }
    }
    return completed && spec_of(stage).output_exists(paths_);
  }

  void sleep_until_next_poll() {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(options_.poll_seconds);
    while (std::chrono::steady_clock::now() < until) {
      reporter_.throw_if_cancelled();
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }

  // Polls until every stage of the range is done or a job failed.
  bool wait() {
    for (;;) {
      reporter_.throw_if_cancelled();
      const std::set<std::string> active = active_job_ids();
      bool all_done = true;
      for (std::size_t s = first_; s <= last_; ++s) {
        if (record_.stages[spec_of(s).name].state == "done") continue;
        if (poll_stage(s, active)) {
          mark_done(s);
        } else {
          all_done = false;
        }
      }
      if (all_done) return true;
      sleep_until_next_poll();
    }
  }

  // True once the job has been missing from squeue without a status file
  // for options_.status_grace_seconds.
  bool grace_over(const std::string& id) {
    const auto now = std::chrono::steady_clock::now();
    const auto first = missing_since_.emplace(id, now).first->second;
    return std::chrono::duration<double>(now - first).count() >= options_.status_grace_seconds;
  }

  // A failed job: the jobs after it can never start (afterok), so they are
  // cancelled; the other tasks of its array go on, and a re-run keeps what
  // they computed. The error names the job's log and keeps its exit code's
  // cause.
  [[noreturn]] void fail(std::size_t job_index,
                         int task,
                         const std::string& id,
                         const TaskStatus& status,
                         const std::set<std::string>& active) {
    const Job& job = jobs_[job_index];
    cancel_jobs(active_ids(active, job_index + 1), reporter_);
    const StageSpec& spec = spec_of(job.stage);
    StageRecord& r = record_.stages[spec.name];
    r.state = "failed";
    r.exit_code = status.exit_code;
    r.finished_at = utc_timestamp();
    save();
    const fs::path log = job.tasks > 0 ? task_log(job, task) : job.log;
    reporter_.error(job.name + (job.tasks > 0 ? " task " + std::to_string(task) : "") + " (Slurm job " + id + ") " +
                    status.reason + "; re-run the same command to submit only what failed again");
    throw_stage_failure(spec.name, status.exit_code > 0 ? status.exit_code : 4, log, "");
  }

  const DriverOptions& driver_;
  const SlurmOptions& options_;
  std::size_t first_, last_;
  const StagePaths& paths_;
  const PipelineConfig& config_;
  RunRecord& record_;
  Reporter& reporter_;
  RunBounds bounds_;  // before jobs_, which are planned from it
  std::vector<Job> jobs_;
  std::map<std::string, std::chrono::steady_clock::time_point> missing_since_;
};

}  // namespace

void check_slurm_available() {
  std::string missing;
  for (const char* program : {"sbatch", "squeue", "scancel", "sinfo"}) {
    if (find_executable(program).empty()) missing += (missing.empty() ? "" : ", ") + std::string(program);
  }
  if (!missing.empty()) {
    throw ConfigError("--executor slurm", "Slurm's commands are not on PATH (missing: " + missing +
                                              "); run on a machine of the cluster, install its client commands "
                                              "(Debian: slurm-client), or use --executor local");
  }
  // sinfo asks the controller, as every later squeue and sbatch will.
  const CommandOutput out = run_command({"sinfo", "--noheader", "--format=%P"});
  if (out.exit_code != 0) {
    throw ConfigError("--executor slurm", "sinfo cannot reach the Slurm controller (exit code " +
                                              std::to_string(out.exit_code) + "): " + trimmed(out.text) +
                                              "; check that slurmctld runs and that this machine's Slurm "
                                              "configuration names it, or use --executor local");
  }
}

bool run_on_slurm(const DriverOptions& driver,
                  const SlurmOptions& options,
                  std::size_t first,
                  std::size_t last,
                  const StagePaths& paths,
                  const PipelineConfig& config,
                  RunRecord& record,
                  Reporter& reporter) {
  return SlurmRun(driver, options, first, last, paths, config, record, reporter).run();
}

}  // namespace hos::pipeline
