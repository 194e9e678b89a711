#include "pipeline/driver/driver.h"

#include <algorithm>
#include <fstream>
#include <functional>
#include <iomanip>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/exit_codes.h"
#include "pipeline/driver/file_hash.h"
#include "pipeline/driver/pipeline_config.h"
#include "pipeline/driver/stage_figures.h"
#include "pipeline/driver/stage_paths.h"
#include "pipeline/sfm/subprocess.h"

namespace hos {
namespace fs = std::filesystem;
namespace {

// How the driver calls one stage executable and what it reads and writes.
struct StageSpec {
  std::string name;
  std::string executable;
  // Arguments naming the stage's inputs and outputs.
  std::function<std::vector<std::string>(const DriverOptions&, const StagePaths&)> arguments;
  // Adds the stage's input files to the fingerprint.
  std::function<void(Fingerprint&, const DriverOptions&, const StagePaths&)> inputs;
  // The stage's result exists (a stage writes it last, atomically).
  std::function<bool(const StagePaths&)> output_exists;
};

void add_undistorted_workspace(Fingerprint& f, const StagePaths& p) {
  f.add_folder_contents(p.undistorted / "sparse");
  f.add_folder_listing(p.undistorted / "images");
}

const std::vector<StageSpec>& stage_specs() {
  static const std::vector<StageSpec> kSpecs{
      {"sfm", "hos-sfm",
       [](const DriverOptions& o, const StagePaths& p) {
         std::vector<std::string> args{"--images", o.photos.string(), "--workspace", p.root.string()};
         if (!o.existing_model.empty()) args.insert(args.end(), {"--sparse", o.existing_model.string()});
         return args;
       },
       [](Fingerprint& f, const DriverOptions& o, const StagePaths&) {
         f.add_folder_listing(o.photos);
         if (!o.existing_model.empty()) f.add_folder_contents(o.existing_model);
       },
       [](const StagePaths& p) { return fs::exists(p.undistorted / "sparse") && fs::exists(p.sfm_report); }},
      {"mvs", "hos-mvs",
       [](const DriverOptions&, const StagePaths& p) {
         return std::vector<std::string>{"--workspace", p.undistorted.string(), "--output", p.points.string()};
       },
       [](Fingerprint& f, const DriverOptions&, const StagePaths& p) { add_undistorted_workspace(f, p); },
       [](const StagePaths& p) { return fs::exists(p.points); }},
      {"recon", "hos-recon",
       [](const DriverOptions&, const StagePaths& p) {
         return std::vector<std::string>{"--input", p.points.string(), "--output", p.mesh.string()};
       },
       [](Fingerprint& f, const DriverOptions&, const StagePaths& p) { f.add_file_contents(p.points); },
       [](const StagePaths& p) { return fs::exists(p.mesh); }},
      {"texture", "hos-texture",
       [](const DriverOptions&, const StagePaths& p) {
         return std::vector<std::string>{"--workspace", p.undistorted.string(), "--mesh", p.mesh.string(),
                                         "--output", p.textured_model.string()};
       },
       [](Fingerprint& f, const DriverOptions&, const StagePaths& p) {
         f.add_file_contents(p.mesh);
         add_undistorted_workspace(f, p);
       },
       [](const StagePaths& p) { return fs::exists(p.textured_model); }},
  };
  return kSpecs;
}

std::size_t stage_index(const std::string& name, const std::string& flag) {
  const auto& specs = stage_specs();
  for (std::size_t i = 0; i < specs.size(); ++i) {
    if (specs[i].name == name) return i;
  }
  throw ConfigError(flag + " " + name, "unknown stage; the stages are: sfm, mvs, recon, texture");
}

std::string config_fingerprint(const PipelineConfig& config, const std::string& stage) {
  Fingerprint f;
  f.add(config.section_yaml(stage));
  return f.hex();
}

// Maps a failed stage's exit code onto the same error kind, so the driver
// exits with the code that names the cause.
[[noreturn]] void throw_stage_failure(const std::string& stage, int code, const fs::path& log) {
  const std::string where = "see " + log.string();
  switch (code) {
    case kExitUsage: throw ConfigError(stage, "the stage rejected its configuration; " + where);
    case kExitBadInput: throw InputError(stage, "the stage rejected its input; " + where);
    case kExitOutputFailed: throw OutputError(stage, "the stage could not write its output; " + where);
    case kExitInterrupted: throw Cancelled();
    default:
      throw StageError(stage, "failed (exit code " + std::to_string(code) + "); " + where);
  }
}

void check_invocation(const DriverOptions& o) {
  std::error_code ec;
  if (o.photos.empty()) throw ConfigError("PHOTOS", "no photo folder given");
  if (!fs::exists(o.photos, ec)) throw InputError(o.photos.string(), "photo folder does not exist");
  if (!fs::is_directory(o.photos, ec)) throw InputError(o.photos.string(), "is not a folder of photos");
  if (!o.existing_model.empty() && !fs::is_directory(o.existing_model, ec)) {
    throw InputError(o.existing_model.string(), "sparse model folder does not exist");
  }
  if (o.output.empty()) throw ConfigError("OUT", "no output file given");
  std::string ext = o.output.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".glb") throw ConfigError(o.output.string(), "the output must be a binary glTF file ending in .glb");
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

DriverResult run_pipeline(const DriverOptions& options, Reporter& reporter) {
  check_invocation(options);
  const auto& specs = stage_specs();
  const std::size_t first = options.from.empty() ? 0 : stage_index(options.from, "--from");
  const std::size_t last = options.to.empty() ? specs.size() - 1 : stage_index(options.to, "--to");
  if (first > last) throw ConfigError("--from " + options.from, "comes after --to " + options.to);

  PipelineConfig config;
  config.apply_preset(options.preset);
  if (!options.config_file.empty()) config.apply_file(options.config_file);
  for (const auto& a : options.assignments) config.apply_assignment(a);
  config.validate();

  // Every stage of the range must exist before anything runs.
  for (std::size_t i = first; i <= last; ++i) {
    const fs::path exe = options.bin_dir / specs[i].executable;
    if (find_executable(exe.string()).empty()) {
      throw StageError("pipeline", specs[i].executable + " is not built (expected " + exe.string() +
                                       "); build it, or stop earlier with --to " +
                                       (i > 0 ? specs[i - 1].name : std::string("STAGE")));
    }
  }

  DriverResult result;
  result.workspace = options.workspace.empty() ? default_workspace(options.output) : options.workspace;
  const StagePaths paths(result.workspace);
  std::error_code ec;
  for (const auto& dir : {paths.root, paths.logs, paths.root / "mvs", paths.root / "recon", paths.root / "texture"}) {
    fs::create_directories(dir, ec);
    if (ec) throw OutputError(dir.string(), "cannot create the workspace folder: " + ec.message());
  }
  write_atomically(paths.config, [&](const fs::path& tmp) {
    std::ofstream out(tmp);
    out << config.resolved_yaml();
    if (!out) throw OutputError(paths.config.string(), "cannot write");
  });
  RunRecord record = load_run_record(paths.run_record);
  record.photos = fs::absolute(options.photos).string();
  record.output = fs::absolute(options.output).string();

  // Stages before --from must have their results already.
  for (std::size_t i = 0; i < first; ++i) {
    if (!specs[i].output_exists(paths)) {
      throw InputError(paths.root.string(), "--from " + specs[first].name + " needs the result of the " +
                                                specs[i].name + " stage, which is not in the workspace; run without --from first");
    }
  }

  bool rerun = options.force;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const StageSpec& spec = specs[i];
    StageOutcome outcome;
    outcome.stage = spec.name;
    if (i < first || i > last) {
      outcome.state = "not run";
      if (record.stages.count(spec.name)) outcome.record = record.stages[spec.name];
      result.stages.push_back(outcome);
      continue;
    }
    reporter.throw_if_cancelled();
    Fingerprint inputs;
    spec.inputs(inputs, options, paths);
    const std::string input_hash = inputs.hex();
    const std::string config_hash = config_fingerprint(config, spec.name);
    StageRecord& stage_record = record.stages[spec.name];
    const bool up_to_date = !rerun && stage_record.state == "done" && stage_record.input_hash == input_hash &&
                            stage_record.config_hash == config_hash && spec.output_exists(paths);
    if (up_to_date) {
      reporter.info(spec.name + ": up to date, skipped");
      outcome.state = "up to date";
      outcome.record = stage_record;
      result.stages.push_back(outcome);
      continue;
    }
    // Everything after a stage that runs depends on its new output.
    rerun = true;
    stage_record = StageRecord{};
    stage_record.state = "running";
    stage_record.input_hash = input_hash;
    stage_record.config_hash = config_hash;
    save_run_record(record, paths.run_record);

    const fs::path log = paths.log(spec.name);
    fs::remove(log, ec);
    ProcessOptions process;
    process.argv = {(options.bin_dir / spec.executable).string()};
    const auto args = spec.arguments(options, paths);
    process.argv.insert(process.argv.end(), args.begin(), args.end());
    process.argv.insert(process.argv.end(), {"--config", paths.config.string(), "--log", log.string(), "--progress",
                                             options.progress});
    if (options.verbose) process.argv.push_back("--verbose");
    process.cancel_source = &reporter;
    std::string command;
    for (const auto& a : process.argv) command += " " + a;
    reporter.info("running " + spec.name);
    reporter.debug("$" + command);
    const ProcessResult run = run_process(process);
    stage_record.wall_seconds = run.wall_seconds;
    stage_record.peak_memory_bytes = run.peak_rss_bytes;
    stage_record.exit_code = run.exit_code;
    stage_record.finished_at = utc_timestamp();
    if (run.cancelled || run.exit_code == kExitInterrupted) {
      stage_record.state = "interrupted";
      save_run_record(record, paths.run_record);
      reporter.error("interrupted during " + spec.name + "; finished stages are kept. Re-run the same command to resume.");
      throw Cancelled();
    }
    if (run.exit_code != 0) {
      stage_record.state = "failed";
      save_run_record(record, paths.run_record);
      throw_stage_failure(spec.name, run.exit_code, log);
    }
    if (!spec.output_exists(paths)) {
      stage_record.state = "failed";
      save_run_record(record, paths.run_record);
      throw StageError(spec.name, "finished without writing its result; see " + log.string());
    }
    stage_record.state = "done";
    stage_record.figures = stage_figures(spec.name, paths.root);
    save_run_record(record, paths.run_record);
    outcome.state = "ran";
    outcome.record = stage_record;
    result.stages.push_back(outcome);
  }

  if (last == specs.size() - 1) {
    write_atomically(options.output, [&](const fs::path& tmp) { fs::copy_file(paths.textured_model, tmp); });
    result.output = options.output;
  }
  return result;
}

std::vector<std::string> summary_table(const DriverResult& result) {
  std::vector<std::string> lines;
  std::ostringstream header;
  header << std::left << std::setw(9) << "stage" << std::setw(12) << "state" << std::setw(11) << "time"
         << std::setw(11) << "peak mem" << "figures";
  lines.push_back(header.str());
  for (const auto& s : result.stages) {
    std::ostringstream row;
    const bool has_record = s.record.state == "done";
    row << std::left << std::setw(9) << s.stage << std::setw(12) << s.state << std::setw(11)
        << (has_record ? format_seconds(s.record.wall_seconds) : "-") << std::setw(11)
        << (has_record ? format_memory(s.record.peak_memory_bytes) : "-")
        << (has_record ? figures_text(s.stage, s.record.figures) : "");
    lines.push_back(row.str());
  }
  lines.push_back("workspace: " + result.workspace.string());
  if (!result.output.empty()) lines.push_back("result: " + result.output.string());
  return lines;
}

}  // namespace hos
