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
#include "synth/video.h"

int main(int argc, char** argv) {
  hos::synth::SceneOptions scene_options;
  hos::synth::DatasetOptions options;
  hos::apps::CommonStageFlags flags;
  std::string output;

  CLI::App app{"hos-synth: render a synthetic scene with ground-truth cameras, mesh and depth"};
  app.add_option("--output", output, "output folder (replaced atomically)")->required();
  app.add_option("--views", options.num_views, "number of views (at least 2)");
  app.add_option("--width", options.width, "image width in pixels");
  app.add_option("--height", options.height, "image height in pixels");
  app.add_option("--focal", options.focal, "focal length in pixels (default 0.9 * width)");
  app.add_option("--seed", scene_options.seed, "scene seed");
  app.add_option("--scene", scene_options.name, "default|rock|torus|box|railing");
  app.add_flag("--ground-plane", scene_options.ground_plane, "add a textured ground plane");
  app.add_flag("--hanging-object", scene_options.hanging_object,
               "add a lantern hanging on a thin wire from a thin pole in front of the objects");
  app.add_option("--rings", options.rings, "elevation rings of views");
  app.add_flag("--jpeg", options.jpeg, "write JPEG instead of PNG images");
  app.add_flag("--depth", options.write_depth, "write depth/view_NNN.tiff (CV_32F z, 0 = empty)");
  app.add_flag("--normals", options.write_normals,
               "write normals/view_NNN.png (16-bit world normal, see docs/synth.md)");
  app.add_option("--supersampling", options.supersampling, "samples per pixel per axis");
  app.add_option("--holdout", options.holdout, "extra held-out views under holdout/");
  app.add_option("--points", options.num_points, "ground-truth sparse points to write");
  app.add_option("--exposure-gains", options.exposure_gains, "per-view exposure gains (one per view)")->delimiter(',');
  app.add_option("--tilt", options.tilt_deg, "turn every camera up (positive) or down by this many degrees");
  std::vector<double> gps;
  app.add_option("--gps", gps,
                 "LAT,LON,ALT: write the views' true positions as GPS EXIF, the scene origin here (--jpeg)")
      ->delimiter(',')
      ->expected(3);
  app.add_option("--metres-per-unit", options.metres_per_unit, "metres of a scene unit for --gps");
  hos::synth::VideoOptions video;
  app.add_option("--video", video.name,
                 "also film the scene: OUTPUT/video/NAME (.mp4 .mov .mkv .avi) and its frames' true cameras in "
                 "OUTPUT/video/sparse");
  app.add_option("--video-frames", video.frames, "frames of the --video clip (one turn around the scene)");
  app.add_option("--video-fps", video.fps, "frame rate of the --video clip");
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
