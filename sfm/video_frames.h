// Video clips as photos: the frames of a clip that SfM should see, chosen by
// sharpness (motion-blurred frames rejected) and by motion (enough parallax
// since the last kept frame), staged as JPEGs that share one camera.
//
// Frame names: a clip staged as NAME gives NAME_fNNNNN.jpg, NNNNN the
// frame's index in the clip (from 0, at least five digits), so the names
// sort in the clip's order (COLMAP's sequential matcher follows the names)
// and a frame's name says where it came from (hos-synth writes the true
// cameras of its video under the same names).
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "core/reporter.h"
#include "sfm/sfm_options.h"

namespace hos::sfm {

struct ImageInputs;

// sfm.video_max_frames, sfm.video_min_motion and sfm.video_blur_ratio
// (sfm_options.h says what they mean).
struct VideoFrameOptions {
  int max_frames = 120;
  double min_motion = 0.05;
  double blur_ratio = 0.6;
};
VideoFrameOptions video_frame_options(const SfmOptions& options);

// Why each frame of a clip was kept or dropped.
struct VideoFrameSelection {
  int frames_read = 0;
  std::vector<int> kept;      // frame indices, increasing
  int blurred = 0;            // dropped: sharpness below blur_ratio of the neighbours'
  int too_little_motion = 0;  // dropped: too close to the last kept frame
  int over_limit = 0;         // dropped by max_frames thinning
  double fps = 0.0;           // as the container states (0 when unknown)
};

// One clip as staged: the selection plus the file and its staged name.
struct VideoClipSummary {
  std::filesystem::path file;
  std::string name;  // staged name of the clip (frames are NAME_fNNNNN.jpg)
  int width = 0;     // of the frames as staged
  int height = 0;
  VideoFrameSelection selection;
};

// "clip.mp4: kept 40 of 300 frames (230 too little motion since the last
// kept frame, 25 motion-blurred, 5 over sfm.video_max_frames)".
std::string describe_selection(const VideoClipSummary& clip);

// True when the file's first bytes are those of a video container (MP4 or
// QuickTime with a video brand, Matroska/WebM, AVI), whatever its name.
// HEIF/AVIF photos (also ISO media files) are not videos.
bool is_video_file(const std::filesystem::path& file);

// The staged name of frame `index` of the clip staged as `clip_name`.
std::string video_frame_name(const std::string& clip_name, int index);

// The frame chooser, fed one frame at a time: pure computation, so it can be
// tested on frames made in memory.
class VideoFrameSelector {
 public:
  explicit VideoFrameSelector(VideoFrameOptions options);
  // First pass: every frame's sharpness, in order.
  void add_sharpness(const cv::Mat& frame);
  // Second pass: the same frames again, in order; true when this one is kept.
  bool keep(const cv::Mat& frame);
  // The selection after the second pass, thinned to max_frames.
  VideoFrameSelection finish();

 private:
  bool is_blurred(int index) const;
  cv::Mat analysis_gray(const cv::Mat& frame) const;
  double tracked_motion(const cv::Mat& gray);
  void start_tracking(const cv::Mat& gray);

  VideoFrameOptions options_;
  std::vector<double> sharpness_;
  int next_ = 0;  // index of the next frame of the second pass
  cv::Mat previous_gray_;
  std::vector<cv::Point2f> start_points_;    // features at the last kept frame
  std::vector<cv::Point2f> current_points_;  // the same features tracked to the previous frame
  int features_at_start_ = 0;                // found at the last kept frame
  VideoFrameSelection selection_;
};

// Sharpness of a frame: the variance of the Laplacian of its grey image.
double frame_sharpness(const cv::Mat& gray);

// Reads the clip twice (sharpness, then motion), writes the kept frames as
// staging_dir/NAME_fNNNNN.jpg (and thumbnails when thumbnail_dir is given,
// as thumbnail_dir/FRAME.jpg) and returns what was kept and why. Frames
// are downscaled to max_image_size (longest side; 0 = keep). Throws
// InputError naming the file when it cannot be decoded or has no frames.
VideoClipSummary stage_video_frames(const std::filesystem::path& file,
                                    const std::string& name,
                                    const std::filesystem::path& staging_dir,
                                    const std::filesystem::path& thumbnail_dir,
                                    const VideoFrameOptions& options,
                                    int max_image_size,
                                    Reporter& reporter);

// prepare_images' hook for a file is_video_file recognised: stages its
// frames into inputs (images and videos, each frame's video_clip set to the
// clip's name), or records it in inputs.skipped with the reason and warns.
void stage_video(const std::filesystem::path& file,
                 const std::string& name,
                 const std::filesystem::path& staging_dir,
                 const std::filesystem::path& thumbnail_dir,
                 const SfmOptions& options,
                 Reporter& reporter,
                 ImageInputs& inputs);

}  // namespace hos::sfm
