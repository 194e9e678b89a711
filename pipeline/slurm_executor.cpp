#include "pipeline/slurm_executor.h"

#include <pwd.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/option_set.h"
#include "core/subprocess.h"
#include "core/view_range.h"
#include "pipeline/file_hash.h"
#include "pipeline/stage_figures.h"
#include "pipeline/stages.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

constexpr const char* kViews = "@VIEWS@";  // stands for the task's "$first-$last" in a script
constexpr const char* kTask = "@TASK@";    // stands for the task's "$task" in a script

// One sbatch submission: a stage, or one part of a stage that splits.
struct Job {
  std::string name;  // "sfm", "mvs-depth", "mvs-fuse", ...: the status file, log and record key
  std::size_t stage = 0;
  std::vector<std::string> argv;
  fs::path log;
  int tasks = 0;  // job array size; 0: a single job
  int chunk = 0;  // views per array task; 0: a task is its index (a tile)
};

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::vector<std::string> with_common_flags(std::vector<std::string> argv,
                                           const fs::path& log,
                                           const StagePaths& paths,
                                           const DriverOptions& driver) {
  argv.insert(argv.end(), {"--config", paths.config.string(), "--log", log.string(), "--progress", "none"});
  if (driver.verbose) argv.push_back("--verbose");
  return argv;
}

std::string part_job_name(const StageSpec& spec) { return spec.name + "-" + spec.split->part_name; }
std::string join_job_name(const StageSpec& spec) { return spec.name + "-" + spec.split->join_name; }

// The array tasks of a stage's parts; 0 when it runs as one job. The number
// of registered views is not known before sfm has run: the files in the
// photo folder bound it (bounds.views), and tasks past the registered views
// compute nothing.
int array_tasks(const StageSpec& spec, const SlurmOptions& options, const PipelineConfig& config, int views) {
  if (!spec.split) return 0;
  if (spec.split->fixed_parts) {
    const int parts = spec.split->fixed_parts(config);
    return parts >= 2 ? parts : 0;
  }
  return std::min(options.tasks_of(spec.name), views);
}

Job stage_job(const std::string& name,
              std::size_t stage,
              const std::vector<std::string>& args,
              const fs::path& log,
              const StagePaths& paths,
              const DriverOptions& driver) {
  Job job;
  job.name = name;
  job.stage = stage;
  job.log = log;
  job.argv.push_back((driver.bin_dir / pipeline_stages()[stage].executable).string());
  job.argv.insert(job.argv.end(), args.begin(), args.end());
  job.argv = with_common_flags(job.argv, job.log, paths, driver);
  return job;
}

std::vector<Job> plan_jobs(const DriverOptions& driver,
                           const SlurmOptions& options,
                           std::size_t first,
                           std::size_t last,
                           const StagePaths& paths,
                           const PipelineConfig& config,
                           const RunBounds& bounds) {
  const auto& specs = pipeline_stages();
  std::vector<Job> jobs;
  for (std::size_t s = first; s <= last; ++s) {
    const StageSpec& spec = specs[s];
    const int tasks = array_tasks(spec, options, config, bounds.views);
    if (tasks == 0) {
      jobs.push_back(stage_job(spec.name, s, spec.arguments(driver, paths), paths.log(spec.name), paths, driver));
      continue;
    }
    const bool over_views = !spec.split->fixed_parts;
    const std::string name = part_job_name(spec);
    Job part = stage_job(name, s, spec.split->part_arguments(paths, over_views ? kViews : kTask),
                         paths.logs / (name + "." + kTask + ".log"), paths, driver);
    part.tasks = tasks;
    part.chunk = over_views ? views_per_task(bounds.views, tasks) : 0;
    jobs.push_back(part);
    jobs.push_back(
        stage_job(join_job_name(spec), s, spec.split->join_arguments(paths), paths.log(spec.name), paths, driver));
  }
  return jobs;
}

// Replaces the first kTask in text by replacement.
std::string with_task(std::string text, const std::string& replacement) {
  const auto at = text.find(kTask);
  if (at != std::string::npos) text.replace(at, std::string(kTask).size(), replacement);
  return text;
}

fs::path status_file(const StagePaths& paths, const Job& job, int task) {
  return paths.root / "slurm" / "status" /
         (job.name + (job.tasks > 0 ? "." + std::to_string(task) : std::string()) + ".exit");
}

fs::path task_log(const Job& job, int task) { return with_task(job.log.string(), std::to_string(task)); }

// The job script: #SBATCH lines for what does not change between
// submissions; the dependency and the array's task list go on sbatch's
// command line.
std::string job_script(const Job& job,
                       const SlurmOptions& options,
                       const PipelineConfig& config,
                       const RunBounds& bounds,
                       const StagePaths& paths) {
  std::ostringstream s;
  s << "#!/bin/sh\n";
  s << "#SBATCH --job-name=hos-" << job.name << "\n";
  s << "#SBATCH --output=" << (paths.logs / (job.name + (job.tasks > 0 ? ".%a" : "") + ".slurm.out")).string() << "\n";
  if (const int mem = job_memory_mb(job.name, config, bounds.views, options.mem_mb)) {
    s << "#SBATCH --mem=" << mem << "M\n";
  }
  const std::string time = job_time_limit(job.name, config, bounds, job.chunk, options.time);
  if (!time.empty()) s << "#SBATCH --time=" << time << "\n";
  if (options.cpus > 0) s << "#SBATCH --cpus-per-task=" << options.cpus << "\n";
  if (!options.partition.empty()) s << "#SBATCH --partition=" << options.partition << "\n";
  if (!options.account.empty()) s << "#SBATCH --account=" << options.account << "\n";
  if (!options.qos.empty()) s << "#SBATCH --qos=" << options.qos << "\n";
  if (!options.constraint.empty()) s << "#SBATCH --constraint=" << options.constraint << "\n";
  s << "task=\"${SLURM_ARRAY_TASK_ID:-0}\"\nstart=$(date +%s)\n";
  if (job.chunk > 0) s << "first=$((task * " << job.chunk << "))\nlast=$((first + " << job.chunk - 1 << "))\n";
  for (std::size_t i = 0; i < job.argv.size(); ++i) {
    const std::string arg = job.argv[i] == kViews ? "\"$first-$last\"" : shell_quote(job.argv[i]);
    s << (i ? " " : "") << with_task(arg, "'\"$task\"'");
  }
  const fs::path status = status_file(paths, job, 0);
  std::string status_text = shell_quote(status.string());
  if (job.tasks > 0) {
    const auto at = status_text.rfind(".0.exit");
    status_text.replace(at, 7, ".'\"$task\"'.exit");
  }
  // The shell's `times` (its children's user and system time, the stage's
  // CPU time) must run in the script's own shell, not in a $(...) subshell.
  s << "\ncode=$?\n";
  s << "times > " << status_text << ".times\n";
  s << "echo \"$code $(($(date +%s) - start)) $(tail -n 1 " << status_text << ".times)\" > " << status_text << "\n";
  s << "rm -f " << status_text << ".times\n";
  s << "exit \"$code\"\n";
  return s.str();
}

struct CommandOutput {
  int exit_code = 0;
  std::string text;
};

CommandOutput run_command(const std::vector<std::string>& argv) {
  ProcessOptions process;
  process.argv = argv;
  CommandOutput out;
  process.on_line = [&](std::string_view line) {
    out.text += line;
    out.text += '\n';
  };
  out.exit_code = run_process(process).exit_code;
  return out;
}

std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

std::string user_name() {
  const passwd* pw = getpwuid(getuid());
  return pw ? pw->pw_name : std::to_string(getuid());
}

// The job ids squeue lists as pending, running or about to end, one per
// array task.
std::set<std::string> active_job_ids() {
  const CommandOutput out = run_command({"squeue", "--noheader", "--array", "--format=%i", "--user=" + user_name()});
  if (out.exit_code != 0) throw StageError("pipeline", "squeue failed: " + trimmed(out.text));
  std::set<std::string> ids;
  std::istringstream lines(out.text);
  for (std::string line; std::getline(lines, line);) {
    if (!trimmed(line).empty()) ids.insert(trimmed(line));
  }
  return ids;
}

// Why a job without a status file ended, from sacct when the cluster keeps
// accounting ("CANCELLED", "OUT_OF_MEMORY", "TIMEOUT", "NODE_FAIL").
std::string sacct_state(const std::string& id) {
  const CommandOutput out =
      run_command({"sacct", "--noheader", "--parsable2", "--allocations", "--format=JobID,State", "--jobs=" + id});
  std::istringstream lines(out.text);
  for (std::string line; out.exit_code == 0 && std::getline(lines, line);) {
    const auto bar = line.find('|');
    if (bar != std::string::npos && line.substr(0, bar) == id) return trimmed(line.substr(bar + 1));
  }
  return "";
}

enum class TaskState { kActive, kCompleted, kFailed };

struct TaskStatus {
  TaskState state = TaskState::kFailed;
  int exit_code = 0;
  std::string reason;
  double seconds = 0;      // the job's wall time, from its status file
  double cpu_seconds = 0;  // its user + system time, from its status file (0: not there)
};

// Seconds of one of `times`' figures: "1m2.5s" (dash, bash).
double times_seconds(const std::string& figure) {
  const auto m = figure.find('m');
  if (m == std::string::npos || figure.empty() || figure.back() != 's') return 0;
  try {
    return std::stod(figure.substr(0, m)) * 60 + std::stod(figure.substr(m + 1, figure.size() - m - 2));
  } catch (const std::exception&) {
    return 0;  // a figure hos cannot read only leaves the CPU time out
  }
}

TaskStatus task_status(const std::string& id, const fs::path& status, const std::set<std::string>& active) {
  if (active.count(id)) return {TaskState::kActive, 0, ""};
  std::ifstream in(status);
  int code = -1;
  double seconds = 0;
  if (in >> code) {
    std::string user, system;
    in >> seconds >> user >> system;
    const double cpu = times_seconds(user) + times_seconds(system);
    if (code == 0) return {TaskState::kCompleted, 0, "", seconds, cpu};
    return {TaskState::kFailed, code, "exit code " + std::to_string(code), seconds, cpu};
  }
  const std::string state = sacct_state(id);
  return {TaskState::kFailed, -1,
          state.empty() ? "ended without a status file (killed?)" : "ended without a status file, sacct: " + state};
}

void cancel_jobs(const std::vector<std::string>& ids, Reporter& reporter) {
  if (ids.empty()) return;
  std::vector<std::string> argv{"scancel"};
  argv.insert(argv.end(), ids.begin(), ids.end());
  const CommandOutput out = run_command(argv);
  std::string list;
  for (const auto& id : ids) list += " " + id;
  if (out.exit_code != 0) {
    reporter.warn("scancel" + list + " failed: " + trimmed(out.text));
  } else {
    reporter.info("cancelled Slurm jobs" + list);
  }
}

// The recorded task ids of a job ("0" -> "13_0"), from run.json.
std::map<int, std::string> recorded_tasks(const nlohmann::ordered_json& entry) {
  std::map<int, std::string> tasks;
  if (!entry.is_object() || !entry.contains("tasks")) return tasks;
  for (const auto& [task, id] : entry.at("tasks").items()) tasks[std::stoi(task)] = id.get<std::string>();
  return tasks;
}

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

  std::string config_hash(std::size_t stage) const {
    Fingerprint f;
    f.add(config_.section_yaml(pipeline_stages()[stage].name));
    return f.hex();
  }
  std::string input_hash(std::size_t stage) const {
    Fingerprint f;
    pipeline_stages()[stage].inputs(f, driver_, paths_);
    return f.hex();
  }

  int task_count(const Job& job) const { return std::max(job.tasks, 1); }

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
    const StageSpec& spec = pipeline_stages()[stage];
    const auto it = record_.stages.find(spec.name);
    if (it == record_.stages.end() || it->second.state != "done") return false;
    return it->second.config_hash == config_hash(stage) && spec.output_exists(paths_) &&
           it->second.input_hash == input_hash(stage);
  }

  void mark_done(std::size_t stage) {
    const StageSpec& spec = pipeline_stages()[stage];
    StageRecord& r = record_.stages[spec.name];
    r.state = "done";
    r.config_hash = config_hash(stage);
    r.input_hash = input_hash(stage);
    r.exit_code = 0;
    r.finished_at = utc_timestamp();
    r.figures = stage_figures(spec.name, paths_.root);
    // Wall time: the stage's jobs one after the other, an array's tasks side
    // by side (the longest counts); CPU time: every task's. Peak memory
    // needs the cluster's accounting, which hos does not rely on: not
    // recorded.
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
    save();
    reporter_.info(spec.name + ": done");
  }

  std::string submit_job(const Job& job, const std::vector<int>& tasks, const std::vector<std::string>& after) {
    const fs::path script = paths_.root / "slurm" / (job.name + ".sh");
    std::error_code ec;
    fs::create_directories(paths_.root / "slurm" / "status", ec);
    write_atomically(script, [&](const fs::path& tmp) {
      std::ofstream out(tmp);
      out << job_script(job, options_, config_, bounds_, paths_);
      if (!out) throw OutputError(script.string(), "cannot write the job script");
    });
    for (int t : tasks) fs::remove(status_file(paths_, job, t), ec);
    std::vector<std::string> argv{"sbatch", "--parsable"};
    if (job.tasks > 0) {
      std::string list;
      for (int t : tasks) list += (list.empty() ? "" : ",") + std::to_string(t);
      argv.push_back("--array=" + list);
    }
    if (!after.empty()) {
      std::string dependency = "--dependency=afterok";
      for (const auto& id : after) dependency += ":" + id;
      argv.push_back(dependency);
    }
    argv.push_back(script.string());
    const CommandOutput out = run_command(argv);
    std::string id = trimmed(out.text.substr(0, out.text.find_first_of(";\n")));
    if (out.exit_code != 0 || id.empty() || id.find_first_not_of("0123456789") != std::string::npos) {
      throw StageError(pipeline_stages()[job.stage].name, "sbatch failed for " + job.name + ": " + trimmed(out.text));
    }
    std::string list;
    for (int t : tasks) list += (list.empty() ? " tasks " : ",") + std::to_string(t);
    reporter_.info("submitted " + job.name + " as Slurm job " + id + (job.tasks > 0 ? list : ""));
    return id;
  }

  // The recorded jobs of a stage that the plan no longer has (recon.tiles
  // changed between one job and an array): their active tasks are cancelled
  // and their entries dropped, so that nothing of them runs on.
  void drop_unplanned_jobs(std::size_t stage, const std::set<std::string>& active) {
    const StageSpec& spec = pipeline_stages()[stage];
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

  // Submits what is not done, pending or running, in stage order; what
  // follows a submission is submitted again too (its input will change).
  void submit() {
    const std::set<std::string> active = active_job_ids();
    bool changed = driver_.force;
    std::vector<std::string> after;  // the active or new jobs the next job waits for
    for (std::size_t s = first_; s <= last_; ++s) {
      const StageSpec& spec = pipeline_stages()[s];
      if (!changed && up_to_date(s)) {
        reporter_.info(spec.name + ": up to date, skipped");
        continue;
      }
      drop_unplanned_jobs(s, active);
      const std::string hash = config_hash(s);
      bool all_completed = true;
      for (const Job& job : jobs_) {
        if (job.stage != s) continue;
        nlohmann::ordered_json& e = entry(job);
        const auto old = recorded_tasks(e);
        const bool reusable = !changed && e.is_object() && e.value("config_hash", "") == hash;
        std::vector<int> to_submit;
        std::vector<std::string> keep, stale;
        for (int t = 0; t < task_count(job); ++t) {
          const auto it = old.find(t);
          if (it == old.end()) {
            to_submit.push_back(t);
            continue;
          }
          const TaskStatus status = task_status(it->second, status_file(paths_, job, t), active);
          if (!reusable) {
            if (status.state == TaskState::kActive) stale.push_back(it->second);
            to_submit.push_back(t);
          } else if (status.state == TaskState::kActive) {
            keep.push_back(it->second);
          } else if (status.state == TaskState::kFailed) {
            reporter_.info(job.name + (job.tasks > 0 ? " task " + std::to_string(t) : "") + " (job " + it->second +
                           ") " + status.reason + "; submitting it again");
            to_submit.push_back(t);
          }
        }
        cancel_jobs(stale, reporter_);
        nlohmann::ordered_json tasks = nlohmann::ordered_json::object();
        for (const auto& [t, id] : old) {
          if (std::find(to_submit.begin(), to_submit.end(), t) == to_submit.end()) tasks[std::to_string(t)] = id;
        }
        if (!to_submit.empty()) {
          const std::string id = submit_job(job, to_submit, after);
          for (int t : to_submit) tasks[std::to_string(t)] = job.tasks > 0 ? id + "_" + std::to_string(t) : id;
          keep.push_back(id);
          changed = true;
        }
        if (!keep.empty()) all_completed = false;
        e = {{"config_hash", hash}, {"array", job.tasks > 0}, {"tasks", tasks}};
        after = keep;
        save();
      }
      if (all_completed && spec.output_exists(paths_)) {
        mark_done(s);
      } else {
        record_.stages[spec.name] = StageRecord{};
        record_.stages[spec.name].state = "submitted";
        record_.stages[spec.name].config_hash = hash;
        save();
      }
    }
  }

  // Polls until every stage of the range is done or a job failed.
  bool wait() {
    for (;;) {
      reporter_.throw_if_cancelled();
      const std::set<std::string> active = active_job_ids();
      bool all_done = true;
      for (std::size_t s = first_; s <= last_; ++s) {
        const StageSpec& spec = pipeline_stages()[s];
        if (record_.stages[spec.name].state == "done") continue;
        bool stage_completed = true;
        for (std::size_t j = 0; j < jobs_.size(); ++j) {
          if (jobs_[j].stage != s) continue;
          for (const auto& [t, id] : recorded_tasks(entry(jobs_[j]))) {
            const TaskStatus status = task_status(id, status_file(paths_, jobs_[j], t), active);
            if (status.state == TaskState::kActive) stage_completed = false;
            if (status.state != TaskState::kFailed) continue;
            if (status.exit_code < 0 && !grace_over(id)) {
              stage_completed = false;  // no status file yet: look again at the next poll
              continue;
            }
            fail(j, t, id, status, active);
          }
        }
        if (stage_completed && spec.output_exists(paths_)) {
          mark_done(s);
        } else {
          all_done = false;
        }
      }
      if (all_done) return true;
      const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(options_.poll_seconds);
      while (std::chrono::steady_clock::now() < until) {
        reporter_.throw_if_cancelled();
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      }
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
    const StageSpec& spec = pipeline_stages()[job.stage];
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

int SlurmOptions::tasks_of(const std::string& stage) const {
  if (stage == "mvs") return mvs_tasks;
  if (stage == "texture") return texture_tasks;
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
  set.add("mvs_tasks", o.mvs_tasks, "array tasks of the mvs depth maps", 1, 100000);
  set.add("texture_tasks", o.texture_tasks, "array tasks of the texture view data", 1, 100000);
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
