#include "sfm/video_frames.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <opencv2/videoio.hpp>
#include <sstream>

#include "core/error.h"
#include "core/jpeg_encoding.h"
#include "core/statistics.h"
#include "sfm/image_inputs.h"

namespace hos::sfm {
namespace fs = std::filesystem;
namespace {

// Sharpness and motion are measured on a grey copy at most this wide: enough
// for corners and blur, and the cost stays flat for 4K clips.
constexpr int kAnalysisSide = 480;
// Frames either side whose median sharpness a frame is compared with: a
// blurred stretch shorter than this is seen as such.
constexpr int kBlurWindow = 10;
constexpr int kMaxTrackedFeatures = 300;
// Tracking is lost (the view has changed much) when fewer than this share
// of the features found at the last kept frame are still tracked.
constexpr double kMinTrackedShare = 0.5;
constexpr int kMinTrackedFeatures = 8;
constexpr int kJpegQuality = 95;

// ISO base media brands of still images (HEIF, AVIF) rather than videos.
bool is_still_image_brand(const std::string& brand) {
  static const std::array<const char*, 10> kBrands{"heic", "heix", "hevc", "hevx", "heim",
                                                   "heis", "mif1", "msf1", "avif", "avis"};
  return std::any_of(kBrands.begin(), kBrands.end(), [&](const char* b) { return brand == b; });
}

}  // namespace

VideoFrameOptions video_frame_options(const SfmOptions& options) {
  return {options.video_max_frames, options.video_min_motion, options.video_blur_ratio};
}

bool is_video_file(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return false;
  std::ifstream in(file, std::ios::binary);
  std::array<char, 12> head{};
  if (!in.read(head.data(), head.size())) return false;
  const std::string box(head.data() + 4, 4);
  const std::string brand(head.data() + 8, 4);
  if (box == "ftyp") return !is_still_image_brand(brand);                 // MP4, MOV, 3GP
  if (box == "moov" || box == "mdat" || box == "wide") return true;       // QuickTime without ftyp
  if (std::memcmp(head.data(), "\x1A\x45\xDF\xA3", 4) == 0) return true;  // Matroska, WebM
  return std::memcmp(head.data(), "RIFF", 4) == 0 && brand == "AVI ";
}

std::string video_frame_name(const std::string& clip_name, int index) {
  std::ostringstream name;
  name << clip_name << "_f" << std::setw(5) << std::setfill('0') << index << ".jpg";
  return name.str();
}

std::string describe_selection(const VideoClipSummary& clip) {
  const VideoFrameSelection& s = clip.selection;
  std::string reasons;
  auto add = [&](int count, const std::string& why) {
    if (count > 0) reasons += format_message(reasons.empty() ? "" : ", ", count, " ", why);
  };
  add(s.too_little_motion, "too little motion since the last kept frame (sfm.video_min_motion)");
  add(s.blurred, "motion-blurred (sfm.video_blur_ratio)");
  add(s.over_limit, "over sfm.video_max_frames");
  return format_message(clip.name, ": kept ", s.kept.size(), " of ", s.frames_read, " frames",
                        reasons.empty() ? std::string() : " (dropped: " + reasons + ")");
}

double frame_sharpness(const cv::Mat& gray) {
  cv::Mat laplacian;
  cv::Laplacian(gray, laplacian, CV_32F);
  cv::Scalar mean, stddev;
  cv::meanStdDev(laplacian, mean, stddev);
  return stddev[0] * stddev[0];
}

VideoFrameSelector::VideoFrameSelector(VideoFrameOptions options) : options_(options) {}

cv::Mat VideoFrameSelector::analysis_gray(const cv::Mat& frame) const {
  cv::Mat gray;
  if (frame.channels() == 1) {
    gray = frame;
  } else {
    cv::cvtColor(frame, gray, frame.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  }
  const int longest = std::max(gray.cols, gray.rows);
  if (longest <= kAnalysisSide) return gray.clone();
  cv::Mat small;
  const double scale = double(kAnalysisSide) / longest;
  cv::resize(gray, small, cv::Size(), scale, scale, cv::INTER_AREA);
  return small;
}

void VideoFrameSelector::add_sharpness(const cv::Mat& frame) {
  sharpness_.push_back(frame_sharpness(analysis_gray(frame)));
}

bool VideoFrameSelector::is_blurred(int index) const {
  if (options_.blur_ratio <= 0) return false;
  const int n = static_cast<int>(sharpness_.size());
  std::vector<double> neighbours;
  for (int k = std::max(0, index - kBlurWindow); k <= std::min(n - 1, index + kBlurWindow); ++k) {
    if (k != index) neighbours.push_back(sharpness_[k]);
  }
  if (neighbours.empty()) return false;
  return sharpness_[index] < options_.blur_ratio * upper_median(std::move(neighbours));
}

void VideoFrameSelector::start_tracking(const cv::Mat& gray) {
  start_points_.clear();
  const double min_distance = std::max(gray.cols, gray.rows) / 50.0;
  cv::goodFeaturesToTrack(gray, start_points_, kMaxTrackedFeatures, 0.01, min_distance);
  current_points_ = start_points_;
  features_at_start_ = static_cast<int>(start_points_.size());
}

// Median distance the features found at the last kept frame have moved
// (analysis pixels); infinite once most of them are lost (the view changed).
double VideoFrameSelector::tracked_motion(const cv::Mat& gray) {
  if (features_at_start_ == 0) return 0.0;  // nothing to track: a blank view gives no parallax
  std::vector<cv::Point2f> next;
  std::vector<unsigned char> status;
  std::vector<float> error;
  if (!current_points_.empty()) {
    cv::calcOpticalFlowPyrLK(previous_gray_, gray, current_points_, next, status, error, cv::Size(21, 21), 3);
  }
  std::vector<cv::Point2f> kept_start, kept_current;
  std::vector<double> moved;
  for (std::size_t i = 0; i < next.size(); ++i) {
    const bool inside = next[i].x >= 0 && next[i].y >= 0 && next[i].x < gray.cols && next[i].y < gray.rows;
    if (!status[i] || !inside) continue;
    kept_start.push_back(start_points_[i]);
    kept_current.push_back(next[i]);
    moved.push_back(cv::norm(next[i] - start_points_[i]));
  }
  start_points_ = std::move(kept_start);
  current_points_ = std::move(kept_current);
  const double still_tracked = static_cast<double>(moved.size());
  if (still_tracked < kMinTrackedFeatures || still_tracked < kMinTrackedShare * features_at_start_) {
    return std::numeric_limits<double>::infinity();
  }
  return upper_median(std::move(moved));
}

bool VideoFrameSelector::keep(const cv::Mat& frame) {
  const int index = next_++;
  if (index >= static_cast<int>(sharpness_.size())) {
    throw std::logic_error("VideoFrameSelector::keep: more frames than add_sharpness saw");
  }
  const cv::Mat gray = analysis_gray(frame);
  bool kept = false;
  if (selection_.kept.empty()) {
    kept = !is_blurred(index);
    selection_.blurred += kept ? 0 : 1;
  } else {
    const double motion = tracked_motion(gray);
    if (motion < options_.min_motion * std::max(gray.cols, gray.rows)) {
      ++selection_.too_little_motion;
    } else if (is_blurred(index)) {
      ++selection_.blurred;
    } else {
      kept = true;
    }
  }
  if (kept) {
    selection_.kept.push_back(index);
    start_tracking(gray);
  }
  previous_gray_ = gray;
  return kept;
}

VideoFrameSelection VideoFrameSelector::finish() {
  VideoFrameSelection s = selection_;
  s.frames_read = static_cast<int>(sharpness_.size());
  const int n = static_cast<int>(s.kept.size());
  const int limit = std::max(1, options_.max_frames);
  if (n > limit) {
    std::vector<int> thinned;
    for (int k = 0; k < limit; ++k) {
      const int at = limit == 1 ? 0 : static_cast<int>(std::lround(double(k) * (n - 1) / (limit - 1)));
      thinned.push_back(s.kept[at]);
    }
    s.over_limit = n - limit;
    s.kept = std::move(thinned);
  }
  return s;
}

namespace {

cv::VideoCapture open_video(const fs::path& file) {
  cv::VideoCapture capture;
  try {
    capture.open(file.string(), cv::CAP_FFMPEG);
  } catch (const cv::Exception&) {
    capture.release();
  }
  if (!capture.isOpened()) {
    throw InputError(file.string(), "cannot be read as a video (OpenCV's FFmpeg reader refused it)");
  }
  return capture;
}

// The frame as staged: at most max_image_size on its longest side.
cv::Mat staged_frame(const cv::Mat& frame, int max_image_size) {
  const int longest = std::max(frame.cols, frame.rows);
  if (max_image_size <= 0 || longest <= max_image_size) return frame;
  cv::Mat small;
  const double scale = double(max_image_size) / longest;
  cv::resize(frame, small, cv::Size(), scale, scale, cv::INTER_AREA);
  return small;
}

// Writes the frame as staging_dir/NAME (and its thumbnail); returns the files.
std::vector<fs::path> write_frame(const cv::Mat& image,
                                  const std::string& name,
                                  const fs::path& staging_dir,
                                  const fs::path& thumbnail_dir) {
  std::vector<fs::path> files{staging_dir / name};
  fs::create_directories(files[0].parent_path());
  write_jpeg_444(image, kJpegQuality, files[0], "the video frame");
  if (!thumbnail_dir.empty()) {
    files.push_back(thumbnail_dir / (name + ".jpg"));
    fs::create_directories(files[1].parent_path());
    write_thumbnail(image, files[1]);
  }
  return files;
}

}  // namespace

VideoClipSummary stage_video_frames(const fs::path& file,
                                    const std::string& name,
                                    const fs::path& staging_dir,
                                    const fs::path& thumbnail_dir,
                                    const VideoFrameOptions& options,
                                    int max_image_size,
                                    Reporter& reporter) {
  VideoClipSummary clip;
  clip.file = file;
  clip.name = name;
  VideoFrameSelector selector(options);
  {
    cv::VideoCapture capture = open_video(file);
    clip.selection.fps = capture.get(cv::CAP_PROP_FPS);
    cv::Mat frame;
    while (capture.read(frame)) {
      reporter.throw_if_cancelled();
      selector.add_sharpness(frame);
    }
  }
  cv::VideoCapture capture = open_video(file);
  cv::Mat frame;
  std::vector<std::pair<int, std::vector<fs::path>>> written;  // frame index, its files
  for (int index = 0; capture.read(frame); ++index) {
    reporter.throw_if_cancelled();
    if (!selector.keep(frame)) continue;
    const cv::Mat image = staged_frame(frame, max_image_size);
    clip.width = image.cols;
    clip.height = image.rows;
    written.emplace_back(index, write_frame(image, video_frame_name(name, index), staging_dir, thumbnail_dir));
  }
  const double fps = clip.selection.fps;
  clip.selection = selector.finish();
  clip.selection.fps = fps;
  if (clip.selection.frames_read == 0) throw InputError(file.string(), "is a video without readable frames");
  // Frames the max_frames thinning dropped were written already.
  const std::vector<int>& kept = clip.selection.kept;
  for (const auto& [index, files] : written) {
    if (std::binary_search(kept.begin(), kept.end(), index)) continue;
    std::error_code ec;
    for (const fs::path& path : files) fs::remove(path, ec);
  }
  return clip;
}

void stage_video(const fs::path& file,
                 const std::string& name,
                 const fs::path& staging_dir,
                 const fs::path& thumbnail_dir,
                 const SfmOptions& options,
                 Reporter& reporter,
                 ImageInputs& inputs) {
  VideoClipSummary clip;
  try {
    clip = stage_video_frames(file, name, staging_dir, thumbnail_dir, video_frame_options(options),
                              options.max_image_size, reporter);
  } catch (const InputError& e) {
    inputs.skipped.push_back({file, e.reason()});
    reporter.warn("skipping " + file.string() + ": " + e.reason());
    return;
  }
  reporter.info(describe_selection(clip));
  for (const int index : clip.selection.kept) {
    StagedImage frame;
    frame.name = video_frame_name(name, index);
    frame.source = file;
    frame.width = clip.width;
    frame.height = clip.height;
    frame.rewritten = true;
    frame.video_clip = name;
    inputs.images.push_back(std::move(frame));
  }
  inputs.videos.push_back(std::move(clip));
}

}  // namespace hos::sfm
