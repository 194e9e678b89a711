// hos-pipeline PHOTOS OUT.glb: photos to a textured mesh, resumable.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>

#include "apps/stage_main.h"
#include "core/exit_codes.h"
#include "pipeline/driver.h"
#include "pipeline/pipeline_config.h"
#include "pipeline/report/report.h"
#include "pipeline/report/report_viewer.h"
#include "pipeline/stages.h"

namespace {

// The stage executables are installed next to hos-pipeline.
std::filesystem::path own_folder(const char* argv0) {
  std::error_code ec;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) return self.parent_path();
  return std::filesystem::absolute(argv0).parent_path();
}

}  // namespace

int main(int argc, char** argv) {
  hos::pipeline::DriverOptions options;
  hos::apps::CommonStageFlags flags;
  bool print_default_config = false;
  std::filesystem::path report_workspace;

  CLI::App app{
      "hos-pipeline: a folder of photos in, a textured mesh (.glb) out.\n"
      "Re-running the same command resumes: stages whose inputs and options are unchanged are skipped."};
  app.add_option("PHOTOS", options.photos, "folder of photos (and video clips), or one video clip");
  app.add_option("OUT", options.output, "output model, format by extension: .glb, .gltf, .obj or .ply");
  app.add_option("--workspace", options.workspace, "workspace folder (default: next to OUT, <OUT name>_workspace)");
  app.add_option("--config", options.config_file,
                 "YAML config file with sections " + hos::pipeline::stage_names_text(":, ") + ":");
  app.add_option("--preset", options.preset, "fast | default | quality, or a YAML file (applied before --config)");
  app.add_option("--set", options.assignments, "override one option: --set recon.lambda=0.2 (repeatable)");
  std::vector<std::string> scale_distance;
  app.add_option("--scale-distance", scale_distance,
                 "A.jpg B.jpg METRES: two photos' camera centres measured on site set the model's scale "
                 "(= --set texture.scale_distance='A.jpg B.jpg METRES')")
      ->expected(3);
  std::filesystem::path masks;
  app.add_option("--masks", masks,
                 "folder of masks: PHOTO.png for each photo PHOTO (its path in PHOTOS), black = not used "
                 "(= --set sfm.masks=DIR; without it, PHOTO.png beside PHOTO)");
  app.add_option("--from", options.from, "first stage to run: " + hos::pipeline::stage_names_text(" | "));
  app.add_option("--to", options.to, "last stage to run: " + hos::pipeline::stage_names_text(" | "));
  app.add_flag("--force", options.force, "run the stages even if they are up to date");
  app.add_option("--sparse", options.existing_model, "existing COLMAP sparse model of PHOTOS: skip SfM");
  app.add_option("--executor", options.executor,
                 "local | slurm: run the stages here, or as Slurm jobs (docs/scale.md)");
  app.add_option("--executor-option", options.executor_options,
                 "KEY=VALUE for the executor (slurm: partition, account, qos, constraint, time, mem_mb, cpus, "
                 "mvs_tasks, texture_tasks, poll_seconds, wait); repeatable");
  app.add_option("--progress", flags.progress, "auto | bar | plain | json | none");
  app.add_option("--log", flags.log_file, "also write the driver's messages to this file");
  app.add_flag("--verbose", flags.verbose, "show debug messages (and the stages' commands)");
  app.add_option("--report", report_workspace, "rewrite WORKSPACE/report.html from the workspace alone and exit")
      ->option_text("WORKSPACE");
  app.add_flag("--print-default-config", print_default_config,
               "print every option of every stage with its default (config/default.yaml) and exit");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? hos::kExitSuccess : hos::kExitUsage;
  }
  if (print_default_config) {
    std::cout << hos::pipeline::default_config_text();
    return hos::kExitSuccess;
  }
  if (!report_workspace.empty()) {
    return hos::apps::run_stage_main("pipeline", flags, [&](hos::Reporter& reporter) {
      const hos::pipeline::ReportOptions report{hos::pipeline::default_viewer_script(own_folder(argv[0]))};
      reporter.info("report: " + hos::pipeline::write_run_report(report_workspace, report).string());
    });
  }
  if (options.photos.empty() || options.output.empty()) {
    std::cerr << "hos-pipeline: error: usage: hos-pipeline PHOTOS OUT.glb [options] (see --help)\n";
    return hos::kExitUsage;
  }
  if (!scale_distance.empty()) {
    options.assignments.push_back("texture.scale_distance=" + scale_distance[0] + " " + scale_distance[1] + " " +
                                  scale_distance[2]);
  }
  if (!masks.empty()) options.assignments.push_back("sfm.masks=" + std::filesystem::absolute(masks).string());
  options.progress = flags.progress;
  options.verbose = flags.verbose;
  options.bin_dir = own_folder(argv[0]);
  return hos::apps::run_stage_main("pipeline", flags, [&](hos::Reporter& reporter) {
    const hos::pipeline::DriverResult result = hos::pipeline::run_pipeline(options, reporter);
    for (const auto& line : hos::pipeline::summary_table(result)) reporter.info(line);
  });
}
