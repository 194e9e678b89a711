// hos-synth: renders a procedural scene with known truth into a dataset
// folder (layout: synth/dataset.h, docs/synth.md).
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>
#include <vector>

#include "apps/stage_main.h"
#include "core/exit_codes.h"
#include "synth/dataset.h"
#include "synth/scene.h"
#include "synth/synth_options.h"
#include "synth/video.h"

int main(int argc, char** argv) {
  hos::synth::SceneOptions scene_options;
  hos::synth::DatasetOptions options;
  hos::apps::CommonStageFlags flags;
  std::string output;

  CLI::App app{"hos-synth: render a synthetic scene with ground-truth cameras, mesh and depth"};
  app.add_option("--output", output, "output folder (replaced atomically)")->required();
  hos::synth::VideoOptions video;
  // One table for the scene, the views and the clip: ranges and
  // documentation in --help, checked like a stage's options.
  hos::OptionSet table("synth");
  register_options(table, scene_options);
  register_options(table, options);
  register_options(table, video);
  hos::apps::add_option_flags(app, flags, table);
  app.add_option("--exposure-gains", options.exposure_gains, "per-view exposure gains (one per view)")->delimiter(',');
  std::vector<double> gps;
  app.add_option("--gps", gps,
                 "LAT,LON,ALT: write the views' true positions as GPS EXIF, the scene origin here (--jpeg)")
      ->delimiter(',')
      ->expected(3);
  app.add_option("--progress", flags.progress, "auto|bar|plain|json|none");
  app.add_option("--log", flags.log_file, "log file");
  app.add_flag("--verbose", flags.verbose, "show debug messages");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? hos::kExitSuccess : hos::kExitUsage;
  }

  if (!gps.empty()) options.gps_origin = hos::GeoPosition{gps[0], gps[1], gps[2]};
  return hos::apps::run_stage_main("synth", flags, [&](hos::Reporter& reporter) {
    hos::apps::apply_config_and_overrides(table, flags);
    scene_options.validate();
    options.validate();
    if (app.count("--video") > 0) video.validate();
    const hos::synth::Scene scene = hos::synth::make_scene(scene_options);
    hos::synth::write_dataset(output, scene, scene_options, options, reporter);
    if (app.count("--video") > 0) {
      hos::synth::write_video(std::filesystem::path(output) / "video", scene, options, video, reporter);
      reporter.info("wrote " + std::to_string(video.frames) + " video frames to " + output + "/video/" + video.name);
    }
    reporter.info("wrote " + std::to_string(options.num_views) + " views to " + output);
  });
}
