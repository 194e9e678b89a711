#include "pipeline/driver.h"

#include <algorithm>
#include <fstream>
#include <functional>
#include <iomanip>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/exit_codes.h"
#include "core/subprocess.h"
#include "pipeline/file_hash.h"
#include "pipeline/output_checks.h"
#include "pipeline/pipeline_config.h"
#include "pipeline/report/report.h"
#include "pipeline/report/report_viewer.h"
#include "pipeline/slurm/slurm_executor.h"
#include "pipeline/stage_failure.h"
#include "pipeline/stage_figures.h"
#include "pipeline/stage_paths.h"
#include "pipeline/stages.h"
#include "pipeline/workspace_lock.h"
#include "sfm/video_frames.h"
#include "texture/model_writer.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

std::string config_fingerprint(const PipelineConfig& config, const std::string& stage) {
  Fingerprint f;
  f.add(config.section_yaml(stage));
  return f.hex();
}

void check_invocation(const DriverOptions& o) {
  std::error_code ec;
  if (o.photos.empty()) throw ConfigError("PHOTOS", "no photo folder given");
  if (!fs::exists(o.photos, ec)) throw InputError(o.photos.string(), "photo folder does not exist");
  if (!fs::is_directory(o.photos, ec) && !sfm::is_video_file(o.photos)) {
    throw InputError(o.photos.string(), "is neither a folder of photos nor a video clip (.mp4 .mov .mkv .avi)");
  }
  if (!o.existing_model.empty() && !fs::is_directory(o.existing_model, ec)) {
    throw InputError(o.existing_model.string(), "sparse model folder does not exist");
  }
  if (o.output.empty()) throw ConfigError("OUT", "no output file given");
  if (!texture::model_format_of(o.output)) {
    throw ConfigError(o.output.string(), std::string("the output must be ") + texture::model_formats_text());
  }
  const fs::path parent = o.output.parent_path().empty() ? fs::path(".") : o.output.parent_path();
  if (!fs::is_directory(parent, ec)) {
    throw OutputError(o.output.string(), "its folder " + parent.string() + " does not exist");
  }
  if (fs::is_directory(o.output, ec)) throw OutputError(o.output.string(), "is a folder");
}

std::string format_seconds(double s) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(1) << s << " s";
  return out.str();
}

std::string format_memory(std::int64_t bytes) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(0) << double(bytes) / (1024.0 * 1024.0) << " MB";
  return out.str();
}

}  // namespace

fs::path default_workspace(const fs::path& output) {
  const fs::path parent = output.parent_path().empty() ? fs::path(".") : output.parent_path();
  return parent / (output.stem().string() + "_workspace");
}

namespace {

// The stages --from and --to select, as indices into pipeline_stages().
struct StageRange {
  std::size_t first = 0, last = 0;
  bool contains(std::size_t i) const { return i >= first && i <= last; }
};

StageRange select_stages(const DriverOptions& options) {
  const auto& specs = pipeline_stages();
  StageRange range;
  range.first = options.from.empty() ? 0 : stage_index(options.from, "--from");
  range.last = options.to.empty() ? specs.size() - 1 : stage_index(options.to, "--to");
  if (range.first > range.last) throw ConfigError("--from " + options.from, "comes after --to " + options.to);
  return range;
}

// Preset, then --config, then every --set; validated.
PipelineConfig load_config(const DriverOptions& options) {
  PipelineConfig config;
  config.apply_preset(options.preset);
  if (!options.config_file.empty()) config.apply_file(options.config_file);
  for (const auto& a : options.assignments) config.apply_assignment(a);
  config.validate();
  return config;
}

// Every stage of the range must exist before anything runs.
void check_executables(const DriverOptions& options, const StageRange& range) {
  const auto& specs = pipeline_stages();
  for (std::size_t i = range.first; i <= range.last; ++i) {
    const fs::path exe = options.bin_dir / specs[i].executable;
    if (find_executable(exe.string()).empty()) {
      throw StageError("pipeline", specs[i].executable + " is not built (expected " + exe.string() +
                                       "); build it, or stop earlier with --to " +
                                       (i > 0 ? specs[i - 1].name : std::string("STAGE")));
    }
  }
}

// The workspace folders and the resolved config.yaml; the workspace (root)
// exists and is locked before this.
void prepare_workspace(const StagePaths& paths, const PipelineConfig& config) {
  std::vector<fs::path> folders{paths.logs};
  for (const StageSpec& spec : pipeline_stages()) folders.push_back(paths.root / spec.name);
  std::error_code ec;
  for (const auto& dir : folders) {
    fs::create_directories(dir, ec);
    if (ec) throw OutputError(dir.string(), "cannot create the workspace folder: " + ec.message());
  }
  write_atomically(paths.config, [&](const fs::path& tmp) {
    std::ofstream out(tmp);
    out << config.resolved_yaml();
    if (!out) throw OutputError(paths.config.string(), "the run's resolved configuration");
  });
}

// Stages before --from must have their results already.
void check_earlier_results(const StageRange& range, const StagePaths& paths) {
  const auto& specs = pipeline_stages();
  for (std::size_t i = 0; i < range.first; ++i) {
    if (!specs[i].output_exists(paths)) {
      throw InputError(paths.root.string(), "--from " + specs[range.first].name + " needs the result of the " +
                                                specs[i].name +
                                                " stage, which is not in the workspace; run without --from first");
    }
  }
}

// The workspace folder, locked against a second run for this one's lifetime.
WorkspaceLock lock_workspace(const StagePaths& paths, Reporter& reporter) {
  std::error_code ec;
  fs::create_directories(paths.root, ec);
  if (ec) throw OutputError(paths.root.string(), "cannot create the workspace folder: " + ec.message());
  return WorkspaceLock(paths.root, reporter);
}

// The hint for a stage that rejects its input: the stage before it wrote it.
std::string input_hint(const StageSpec& spec) {
  const auto& specs = pipeline_stages();
  for (std::size_t i = 1; i < specs.size(); ++i) {
    if (specs[i].name == spec.name) return damaged_intermediate_hint(specs[i - 1].name);
  }
  return "";
}

// Runs one stage executable and records how it went; throws on failure.
void run_stage_process(const StageSpec& spec,
                       const DriverOptions& options,
                       const StagePaths& paths,
                       RunRecord& record,
                       StageRecord& stage_record,
                       Reporter& reporter) {
  warn_if_low_space(paths.root, spec.disk_bytes(options.photos, paths), spec.name, reporter);
  const fs::path log = paths.log(spec.name);
  std::error_code ec;
  fs::remove(log, ec);
  ProcessOptions process;
  process.argv = {(options.bin_dir / spec.executable).string()};
  const auto args = spec.arguments(options, paths);
  process.argv.insert(process.argv.end(), args.begin(), args.end());
  process.argv.insert(process.argv.end(),
                      {"--config", paths.config.string(), "--log", log.string(), "--progress", options.progress});
  if (options.verbose) process.argv.push_back("--verbose");
  process.cancel_source = &reporter;
  std::string command;
  for (const auto& a : process.argv) command += " " + a;
  reporter.info("running " + spec.name);
  reporter.debug("$" + command);
  const ProcessResult run = run_process(process);
  stage_record.wall_seconds = run.wall_seconds;
  stage_record.cpu_seconds = run.cpu_seconds;
  stage_record.peak_memory_bytes = run.peak_rss_bytes;
  stage_record.exit_code = run.exit_code;
  stage_record.finished_at = utc_timestamp();
  if (run.cancelled || run.exit_code == kExitInterrupted) {
    stage_record.state = "interrupted";
    save_run_record(record, paths.run_record);
    reporter.error("interrupted during " + spec.name +
                   "; finished stages are kept. Re-run the same command to resume.");
    throw Cancelled();
  }
  if (run.exit_code != 0) {
    stage_record.state = "failed";
    save_run_record(record, paths.run_record);
    throw_stage_failure(spec.name, run.exit_code, log, input_hint(spec));
  }
  if (!spec.output_exists(paths)) {
    stage_record.state = "failed";
    save_run_record(record, paths.run_record);
    throw StageError(spec.name, "finished without writing its result; see " + log.string());
  }
  stage_record.state = "done";
  stage_record.figures = stage_figures(spec.name, paths.root);
  save_run_record(record, paths.run_record);
}

// Runs a stage of the range unless its inputs and config are unchanged since
// its last successful run; `rerun` forces it and is set once a stage ran,
// since everything after depends on its new output.
StageOutcome run_or_skip_stage(const StageSpec& spec,
                               const DriverOptions& options,
                               const StagePaths& paths,
                               const PipelineConfig& config,
                               RunRecord& record,
                               bool& rerun,
                               Reporter& reporter) {
  StageOutcome outcome;
  outcome.stage = spec.name;
  Fingerprint inputs;
  spec.inputs(inputs, options, config, paths);
  const std::string input_hash = inputs.hex();
  const std::string config_hash = config_fingerprint(config, spec.name);
  StageRecord& stage_record = record.stages[spec.name];
  const bool up_to_date = !rerun && stage_record.state == "done" && stage_record.input_hash == input_hash &&
                          stage_record.config_hash == config_hash && spec.output_exists(paths);
  if (up_to_date) {
    reporter.info(spec.name + ": up to date, skipped");
    outcome.state = "up to date";
    outcome.record = stage_record;
    return outcome;
  }
  rerun = true;
  stage_record = StageRecord{};
  stage_record.state = "running";
  stage_record.input_hash = input_hash;
  stage_record.config_hash = config_hash;
  save_run_record(record, paths.run_record);
  run_stage_process(spec, options, paths, record, stage_record, reporter);
  outcome.state = "ran";
  outcome.record = stage_record;
  return outcome;
}

// Runs or skips every stage of the range and copies the result to OUT.
void run_stage_range(const DriverOptions& options,
                     const StageRange& range,
                     const StagePaths& paths,
                     const PipelineConfig& config,
                     RunRecord& record,
                     DriverResult& result,
                     Reporter& reporter) {
  const auto& specs = pipeline_stages();
  bool rerun = options.force;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    if (range.contains(i)) {
      reporter.throw_if_cancelled();
      result.stages.push_back(run_or_skip_stage(specs[i], options, paths, config, record, rerun, reporter));
    } else {
      StageOutcome outcome{specs[i].name, "not run", {}};
      if (record.stages.count(specs[i].name)) outcome.record = record.stages[specs[i].name];
      result.stages.push_back(outcome);
    }
  }
  if (range.last == specs.size() - 1) {
    copy_result(paths.textured_model, options.output);
    result.output = options.output;
  }
}

// A report that cannot be written must not hide how the run went.
void write_report_or_warn(const DriverOptions& options, const fs::path& workspace, Reporter& reporter) {
  try {
    reporter.info("report: " + write_run_report(workspace, {default_viewer_script(options.bin_dir)}).string());
  } catch (const std::exception& e) {
    reporter.warn(std::string("could not write the run report: ") + e.what());
  }
}

}  // namespace

DriverResult run_pipeline(const DriverOptions& options, Reporter& reporter) {
  check_invocation(options);
  if (options.executor != "local" && options.executor != "slurm") {
    throw ConfigError("--executor " + options.executor, "unknown executor; the executors are local and slurm");
  }
  if (options.executor == "local" && !options.executor_options.empty()) {
    throw ConfigError("--executor-option " + options.executor_options.front(), "needs --executor slurm");
  }
  const SlurmOptions slurm = parse_slurm_options(options.executor_options);
  const StageRange range = select_stages(options);
  const PipelineConfig config = load_config(options);
  check_executables(options, range);
  if (options.executor == "slurm") check_slurm_available();  // before the workspace is made
  const auto& specs = pipeline_stages();
  if (range.last == specs.size() - 1) check_writable_target(options.output);

  DriverResult result;
  result.workspace = options.workspace.empty() ? default_workspace(options.output) : options.workspace;
  const StagePaths paths(result.workspace);
  check_earlier_results(range, paths);  // before anything is created in the workspace
  const WorkspaceLock lock = lock_workspace(paths, reporter);
  prepare_workspace(paths, config);
  RunRecord record = load_run_record(paths.run_record);
  record.photos = fs::absolute(options.photos).string();
  record.output = fs::absolute(options.output).string();

  // The report is written however the run ends: a failed or interrupted
  // run's page shows how far it got.
  try {
    if (options.executor == "slurm") {
      // Stages run as Slurm jobs; the result is copied once they are done.
      if (run_on_slurm(options, slurm, range.first, range.last, paths, config, record, reporter) &&
          range.last == specs.size() - 1) {
        copy_result(paths.textured_model, options.output);
        result.output = options.output;
      }
      for (std::size_t i = 0; i < specs.size(); ++i) {
        const auto it = record.stages.find(specs[i].name);
        const bool done = range.contains(i) && it != record.stages.end() && it->second.state == "done";
        result.stages.push_back({specs[i].name,
                                 done                ? "done"
                                 : range.contains(i) ? "submitted"
                                                     : "not run",
                                 it != record.stages.end() ? it->second : StageRecord{}});
      }
    } else {
      run_stage_range(options, range, paths, config, record, result, reporter);
    }
  } catch (...) {
    write_report_or_warn(options, paths.root, reporter);
    throw;
  }
  write_report_or_warn(options, paths.root, reporter);
  return result;
}

std::vector<std::string> summary_table(const DriverResult& result) {
  std::vector<std::string> lines;
  std::ostringstream header;
  header << std::left << std::setw(9) << "stage" << std::setw(12) << "state" << std::setw(11) << "time" << std::setw(11)
         << "cpu" << std::setw(11) << "peak mem"
         << "figures";
  lines.push_back(header.str());
  for (const auto& s : result.stages) {
    std::ostringstream row;
    const bool has_record = s.record.state == "done";
    row << std::left << std::setw(9) << s.stage << std::setw(12) << s.state << std::setw(11)
        << (has_record ? format_seconds(s.record.wall_seconds) : "-") << std::setw(11)
        << (has_record && s.record.cpu_seconds > 0 ? format_seconds(s.record.cpu_seconds) : "-") << std::setw(11)
        << (has_record && s.record.peak_memory_bytes > 0 ? format_memory(s.record.peak_memory_bytes) : "-")
        << (has_record ? figures_text(s.stage, s.record.figures) : "");
    lines.push_back(row.str());
  }
  lines.push_back("workspace: " + result.workspace.string());
  if (!result.output.empty()) lines.push_back("result: " + result.output.string());
  return lines;
}

}  // namespace hos::pipeline
