#include "synth/video.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numbers>
#include <opencv2/videoio.hpp>
#include <sstream>

#include "core/atomic_file.h"
#include "core/colmap_io.h"
#include "core/error.h"
#include "core/text.h"
#include "synth/synth_options.h"

namespace hos::synth {
namespace fs = std::filesystem;
namespace {

// The elevations of the dataset's lowest and highest rings (view_directions).
constexpr double kLowestElevationDeg = 15.0;
constexpr double kHighestElevationDeg = 50.0;
constexpr double kElevationSwingsPerTurn = 2.0;

// H.264 (FFmpeg's libx264) as phones write; OpenCV's own MJPEG for AVI.
int fourcc_for(const std::string& name) {
  if (lower_case_extension(name) == ".avi") return cv::VideoWriter::fourcc('M', 'J', 'P', 'G');
  return cv::VideoWriter::fourcc('a', 'v', 'c', '1');
}

}  // namespace

void VideoOptions::validate() const {
  const std::string ext = lower_case_extension(name);
  if (name.empty() || fs::path(name).filename() != name) {
    throw ConfigError("video", "'" + name + "' must be a plain file name (the clip goes into the dataset's video/)");
  }
  if (ext != ".mp4" && ext != ".mov" && ext != ".mkv" && ext != ".avi") {
    throw ConfigError("video", "'" + name + "' must end in .mp4, .mov, .mkv or .avi");
  }
  check_option_table("synth", *this);
}

std::string video_frame_file_name(const std::string& clip_name, int index) {
  std::ostringstream name;
  name << clip_name << "_f" << std::setw(5) << std::setfill('0') << index << ".jpg";
  return name.str();
}

SparseModel make_video_cameras(const Scene& scene, const DatasetOptions& dataset, const VideoOptions& video) {
  dataset.validate();
  video.validate();
  SparseModel model;
  const Camera camera = dataset_camera(dataset);
  model.cameras.emplace(1, camera);
  const double middle = 0.5 * (kLowestElevationDeg + kHighestElevationDeg) * std::numbers::pi / 180.0;
  const double swing = 0.5 * (kHighestElevationDeg - kLowestElevationDeg) * std::numbers::pi / 180.0;
  for (int k = 0; k < video.frames; ++k) {
    // Along the path: k / frames of the way, the last frame one step short
    // of the first so a whole turn does not repeat it.
    const double along = video.turns * k / video.frames;
    const double azimuth = 2 * std::numbers::pi * along;
    const double elevation = middle - swing * std::cos(2 * std::numbers::pi * kElevationSwingsPerTurn * along);
    ImageRecord image = view_towards_centre(scene, camera, elevation, azimuth);
    image.id = k + 1;
    image.camera_id = 1;
    image.name = video_frame_file_name(video.name, k);
    model.images.emplace(image.id, std::move(image));
  }
  return model;
}

void write_video(const fs::path& folder,
                 const Scene& scene,
                 const DatasetOptions& dataset,
                 const VideoOptions& video,
                 Reporter& reporter) {
  const SparseModel model = make_video_cameras(scene, dataset, video);
  const Camera& camera = model.cameras.at(1);
  render::RenderOptions render_options;
  render_options.supersampling = dataset.supersampling;
  write_folder_atomically(folder, [&](const fs::path& tmp) {
    const fs::path clip = tmp / video.name;
    cv::VideoWriter writer;
    writer.open(clip.string(), cv::CAP_FFMPEG, fourcc_for(video.name), video.fps,
                cv::Size(camera.width, camera.height));
    if (!writer.isOpened()) {
      throw OutputError((folder / video.name).string(), "no video encoder of OpenCV's FFmpeg takes this container");
    }
    reporter.begin("rendering video frames", video.frames);
    for (const auto& [id, image] : model.images) {
      reporter.throw_if_cancelled();
      writer.write(render::render_view(scene.objects, camera, image, render_options).color);
      reporter.advance();
    }
    reporter.end();
    writer.release();
    write_colmap_model(model, tmp / "sparse", ColmapFormat::kText);
  });
}

}  // namespace hos::synth
