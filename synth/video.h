// A video of a synthetic scene: the camera moves smoothly around it, as a
// phone filmed walking around an object, with the true camera of every
// frame so that a reconstruction from the clip can be measured.
//
// Output layout of write_video (DIR/video/ of hos-synth --video NAME):
//   DIR/video/NAME                  the clip (H.264 in .mp4/.mov/.mkv, MJPEG in .avi)
//   DIR/video/sparse/{cameras,images,points3D}.txt
//                                   the frames' true cameras, one PINHOLE camera,
//                                   image k named NAME_fNNNNN.jpg: the name the
//                                   sfm stage stages frame k under
//                                   (sfm/video_frames.h), so hos-eval can align a
//                                   reconstruction from the clip by name
#pragma once

#include <filesystem>
#include <string>

#include "core/reporter.h"
#include "core/sparse_model.h"
#include "synth/dataset.h"
#include "synth/scene.h"

namespace hos::synth {

struct VideoOptions {
  std::string name = "clip.mp4";  // file name; its extension picks the container
  int frames = 240;
  double fps = 30.0;
  // The path: one turn around the scene centre while the elevation swings
  // twice between the dataset's lowest and highest rings (15 and 50
  // degrees), so the clip sees what the two rings of views see.
  double turns = 1.0;
  void validate() const;  // throws ConfigError
};

// "clip.mp4_f00012.jpg": the name of frame `index` (sfm/video_frames.h).
std::string video_frame_file_name(const std::string& clip_name, int index);

// The true cameras of the frames (the dataset's camera, images named by
// video_frame_file_name).
SparseModel make_video_cameras(const Scene& scene, const DatasetOptions& dataset, const VideoOptions& video);

// Renders the frames and writes the layout above into folder (replaced
// atomically). Throws OutputError when no encoder takes the clip.
void write_video(const std::filesystem::path& folder,
                 const Scene& scene,
                 const DatasetOptions& dataset,
                 const VideoOptions& video,
                 Reporter& reporter = null_reporter());

}  // namespace hos::synth
