#include "synth/synth_options.h"

#include <limits>

namespace hos::synth {

void register_options(OptionSet& set, SceneOptions& o) {
  set.add("seed", o.seed, "scene seed", std::uint32_t{0}, std::numeric_limits<std::uint32_t>::max());
  set.add_choice("scene", o.name, scene_names(), "default (rock, torus, box), rock, torus, box or railing (thin bars)");
  set.add("ground_plane", o.ground_plane, "add a textured ground plane");
  set.add("hanging_object", o.hanging_object,
          "add a lantern hanging on a thin wire from a thin pole in front of the objects");
  set.add_flag("--seed", "seed");
  set.add_flag("--scene", "scene");
  set.add_flag("--ground-plane", "ground_plane", "true");
  set.add_flag("--hanging-object", "hanging_object", "true");
}

void register_options(OptionSet& set, DatasetOptions& o) {
  set.add("views", o.num_views, "number of views", 2, 100000);
  set.add("width", o.width, "image width in pixels", 16, 65536);
  set.add("height", o.height, "image height in pixels", 16, 65536);
  set.add("focal", o.focal, "focal length in pixels (0 = 0.9 * width)", 0.0, 1e7);
  set.add("rings", o.rings, "elevation rings of views", 1, 1000);
  set.add("jpeg", o.jpeg, "write JPEG instead of PNG images");
  set.add("depth", o.write_depth, "write depth/view_NNN.tiff (CV_32F z, 0 = empty)");
  set.add("normals", o.write_normals, "write normals/view_NNN.png (16-bit world normal, see docs/synth.md)");
  set.add("supersampling", o.supersampling, "samples per pixel per axis", 1, 8);
  set.add("holdout", o.holdout, "extra held-out views under holdout/", 0, 100000);
  set.add("points", o.num_points, "ground-truth sparse points to write", 0, 100000000);
  set.add("tilt_deg", o.tilt_deg, "turn every camera up (positive) or down by this many degrees", -60.0, 60.0);
  set.add("metres_per_unit", o.metres_per_unit, "metres of a scene unit for --gps", 1e-9, 1e9);
  set.add("masked_views", o.masked_views,
          "the first N photos get a magenta box painted in and masks/NAME.png masking it out", 0, 100000);
  set.add_flag("--views", "views");
  set.add_flag("--width", "width");
  set.add_flag("--height", "height");
  set.add_flag("--focal", "focal");
  set.add_flag("--rings", "rings");
  set.add_flag("--jpeg", "jpeg", "true");
  set.add_flag("--depth", "depth", "true");
  set.add_flag("--normals", "normals", "true");
  set.add_flag("--supersampling", "supersampling");
  set.add_flag("--holdout", "holdout");
  set.add_flag("--points", "points");
  set.add_flag("--tilt", "tilt_deg");
  set.add_flag("--metres-per-unit", "metres_per_unit");
  set.add_flag("--masked-views", "masked_views");
}

void register_options(OptionSet& set, VideoOptions& o) {
  set.add("video.name", o.name,
          "also film the scene: OUTPUT/video/NAME (.mp4 .mov .mkv .avi) and its frames' true cameras in "
          "OUTPUT/video/sparse");
  set.add("video.frames", o.frames, "frames of the --video clip (one turn around the scene)", 3, 1000000);
  set.add("video.fps", o.fps, "frame rate of the --video clip", 0.01, 1000.0);
  set.add("video.turns", o.turns, "turns around the scene centre the clip makes", 0.01, 100.0);
  set.add_flag("--video", "video.name");
  set.add_flag("--video-frames", "video.frames");
  set.add_flag("--video-fps", "video.fps");
}

}  // namespace hos::synth
