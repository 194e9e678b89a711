#include "pipeline/slurm/slurm_jobs.h"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "core/view_range.h"
#include "pipeline/slurm/slurm_commands.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

constexpr const char* kViews = "@VIEWS@";  // stands for the task's "$first-$last" in a script
constexpr const char* kTask = "@TASK@";    // stands for the task's "$task" in a script

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

// Replaces the first kTask in text by replacement.
std::string with_task(std::string text, const std::string& replacement) {
  const auto at = text.find(kTask);
  if (at != std::string::npos) text.replace(at, std::string(kTask).size(), replacement);
  return text;
}

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

}  // namespace

std::string part_job_name(const StageSpec& spec) { return spec.name + "-" + spec.split->part_name; }

std::string join_job_name(const StageSpec& spec) { return spec.name + "-" + spec.split->join_name; }

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

fs::path status_file(const StagePaths& paths, const Job& job, int task) {
  std::string name = job.name;
  if (job.tasks > 0) name.append(".").append(std::to_string(task));
  return paths.root / "slurm" / "status" / (name + ".exit");
}

fs::path task_log(const Job& job, int task) { return with_task(job.log.string(), std::to_string(task)); }

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

}  // namespace hos::pipeline
