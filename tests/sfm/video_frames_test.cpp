#include "sfm/video_frames.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "core/error.h"
#include "sfm/colmap_steps.h"
#include "sfm/image_inputs.h"
#include "sfm/sfm_plan.h"
#include "tests/support/test_support.h"

namespace hos::sfm {
namespace {
namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr int kFrameWidth = 320;
constexpr int kFrameHeight = 240;

// A wide textured strip; a frame is a window of it, so moving the window
// moves every feature by the same number of pixels.
cv::Mat texture_strip(int width) {
  cv::Mat noise(kFrameHeight, width, CV_8UC3);
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 255);
  cv::Mat strip;
  cv::GaussianBlur(noise, strip, cv::Size(0, 0), 1.5);
  return strip;
}

// Frame positions (left edge in the strip, pixels) and which frame is blurred.
struct Clip {
  std::vector<int> offsets;
  int blurred = -1;
};

std::vector<cv::Mat> render(const Clip& clip) {
  const int widest = *std::max_element(clip.offsets.begin(), clip.offsets.end()) + kFrameWidth;
  const cv::Mat strip = texture_strip(widest);
  std::vector<cv::Mat> frames;
  for (std::size_t i = 0; i < clip.offsets.size(); ++i) {
    cv::Mat frame = strip(cv::Rect(clip.offsets[i], 0, kFrameWidth, kFrameHeight)).clone();
    // Motion blur along the motion: a horizontal box filter 15 px wide.
    if (static_cast<int>(i) == clip.blurred) cv::blur(frame, frame, cv::Size(15, 1));
    frames.push_back(frame);
  }
  return frames;
}

VideoFrameSelection select(const std::vector<cv::Mat>& frames, const VideoFrameOptions& options) {
  VideoFrameSelector selector(options);
  for (const cv::Mat& frame : frames) selector.add_sharpness(frame);
  for (const cv::Mat& frame : frames) selector.keep(frame);
  return selector.finish();
}

// 10 frames standing still, then 60 frames moving 4 px a frame.
Clip still_then_moving(int blurred = -1) {
  Clip clip;
  for (int i = 0; i < 10; ++i) clip.offsets.push_back(0);
  for (int i = 1; i <= 60; ++i) clip.offsets.push_back(4 * i);
  clip.blurred = blurred;
  return clip;
}

TEST(VideoFrameSelector, StillFramesAreDroppedAndMovingOnesKeptAtTheMotionStep) {
  VideoFrameOptions options;
  options.min_motion = 0.05;  // 16 px of 320: every 4th moving frame
  const VideoFrameSelection s = select(render(still_then_moving()), options);
  EXPECT_EQ(s.frames_read, 70);
  ASSERT_FALSE(s.kept.empty());
  EXPECT_EQ(s.kept.front(), 0);
  // None of the duplicates of frame 0 is kept.
  EXPECT_TRUE(std::none_of(s.kept.begin(), s.kept.end(), [](int i) { return i > 0 && i < 10; }));
  // Moving: 240 px in steps of at least 16 px, so 15 frames at most.
  EXPECT_GE(s.kept.size(), 13u);
  EXPECT_LE(s.kept.size(), 16u);
  for (std::size_t k = 1; k < s.kept.size(); ++k) {
    const int moved = 4 * (s.kept[k] - std::max(s.kept[k - 1], 9));
    EXPECT_GE(moved, 15) << "frames " << s.kept[k - 1] << " and " << s.kept[k];
    EXPECT_LE(moved, 20) << "frames " << s.kept[k - 1] << " and " << s.kept[k];
  }
  EXPECT_EQ(s.blurred, 0);
  EXPECT_EQ(s.too_little_motion + static_cast<int>(s.kept.size()), 70);
}

TEST(VideoFrameSelector, BlurredFrameIsDroppedAndTheNextSharpOneTaken) {
  // Every frame moves 20 px, more than min_motion: all are due, one is blurred.
  Clip clip;
  for (int i = 0; i < 30; ++i) clip.offsets.push_back(20 * i);
  clip.blurred = 12;
  const VideoFrameSelection s = select(render(clip), VideoFrameOptions{});
  EXPECT_EQ(s.blurred, 1);
  EXPECT_FALSE(std::binary_search(s.kept.begin(), s.kept.end(), 12));
  EXPECT_TRUE(std::binary_search(s.kept.begin(), s.kept.end(), 13));
  EXPECT_EQ(s.kept.size(), 29u);
}

TEST(VideoFrameSelector, BlurredFrameInAStillThenMovingClipIsNeverKept) {
  for (const int blurred : {5, 31, 33}) {
    const VideoFrameSelection s = select(render(still_then_moving(blurred)), VideoFrameOptions{});
    EXPECT_FALSE(std::binary_search(s.kept.begin(), s.kept.end(), blurred)) << "blurred frame " << blurred;
    EXPECT_EQ(s.blurred + s.too_little_motion + static_cast<int>(s.kept.size()), 70);
  }
}

TEST(VideoFrameSelector, BlurRatioZeroKeepsBlurredFrames) {
  Clip clip;
  for (int i = 0; i < 30; ++i) clip.offsets.push_back(20 * i);
  clip.blurred = 12;
  VideoFrameOptions options;
  options.blur_ratio = 0.0;
  const VideoFrameSelection s = select(render(clip), options);
  EXPECT_EQ(s.blurred, 0);
  EXPECT_EQ(s.kept.size(), 30u);
}

TEST(VideoFrameSelector, MaxFramesThinsEvenly) {
  Clip clip;
  for (int i = 0; i < 40; ++i) clip.offsets.push_back(20 * i);
  VideoFrameOptions options;
  options.max_frames = 10;
  const VideoFrameSelection s = select(render(clip), options);
  ASSERT_EQ(s.kept.size(), 10u);
  EXPECT_EQ(s.over_limit, 30);
  EXPECT_EQ(s.kept.front(), 0);
  EXPECT_EQ(s.kept.back(), 39);
  for (std::size_t k = 1; k < s.kept.size(); ++k) {
    EXPECT_GE(s.kept[k] - s.kept[k - 1], 4);
    EXPECT_LE(s.kept[k] - s.kept[k - 1], 5);
  }
}

TEST(VideoFrameSelector, FrameSharpnessFallsWithBlur) {
  const cv::Mat sharp = texture_strip(kFrameWidth);
  cv::Mat gray, blurred;
  cv::cvtColor(sharp, gray, cv::COLOR_BGR2GRAY);
  cv::blur(gray, blurred, cv::Size(15, 1));
  EXPECT_LT(frame_sharpness(blurred), 0.3 * frame_sharpness(gray));
}

TEST(VideoFrames, FrameNamesSortInClipOrder) {
  EXPECT_EQ(video_frame_name("clip.mp4", 12), "clip.mp4_f00012.jpg");
  EXPECT_EQ(video_frame_name("a/b.mov", 123456), "a/b.mov_f123456.jpg");
  EXPECT_LT(video_frame_name("clip.mp4", 9), video_frame_name("clip.mp4", 10));
}

void write_bytes(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

TEST(VideoFrames, VideoFilesAreRecognisedByContent) {
  hos::testing::TempDir dir;
  const std::string z4("\0\0\0\x18", 4);
  write_bytes(dir / "phone.jpg", z4 + "ftypisom" + std::string(20, '\0'));  // an MP4 whatever its name
  write_bytes(dir / "quicktime", z4 + "ftypqt  " + std::string(20, '\0'));
  write_bytes(dir / "clip.mkv", std::string("\x1A\x45\xDF\xA3", 4) + std::string(20, '\0'));
  write_bytes(dir / "clip.avi", std::string("RIFF\x10\0\0\0AVI LIST", 16) + std::string(20, '\0'));
  write_bytes(dir / "photo.heic", z4 + "ftypheic" + std::string(20, '\0'));
  write_bytes(dir / "photo.avif", z4 + "ftypavif" + std::string(20, '\0'));
  write_bytes(dir / "fake.mp4", "\xFF\xD8\xFF\xE0 not a video at all");
  write_bytes(dir / "short.mp4", "abc");
  EXPECT_TRUE(is_video_file(dir / "phone.jpg"));
  EXPECT_TRUE(is_video_file(dir / "quicktime"));
  EXPECT_TRUE(is_video_file(dir / "clip.mkv"));
  EXPECT_TRUE(is_video_file(dir / "clip.avi"));
  EXPECT_FALSE(is_video_file(dir / "photo.heic"));
  EXPECT_FALSE(is_video_file(dir / "photo.avif"));
  EXPECT_FALSE(is_video_file(dir / "fake.mp4"));
  EXPECT_FALSE(is_video_file(dir / "short.mp4"));
  EXPECT_FALSE(is_video_file(dir / "missing.mp4"));
  EXPECT_FALSE(is_video_file(dir.path()));
}

// Writes the clip as an MJPEG AVI (OpenCV's own encoder: always there).
fs::path write_clip(const fs::path& file, const std::vector<cv::Mat>& frames) {
  cv::VideoWriter writer(file.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 30.0,
                         cv::Size(kFrameWidth, kFrameHeight));
  if (!writer.isOpened()) throw std::runtime_error("cannot write " + file.string());
  for (const cv::Mat& frame : frames) writer.write(frame);
  return file;
}

TEST(VideoFrames, PrepareImagesStagesTheKeptFramesOfAClipAsOneCamera) {
  hos::testing::TempDir dir;
  fs::create_directories(dir / "photos");
  write_clip(dir / "photos" / "walk.avi", render(still_then_moving(30)));
  const ImageInputs inputs =
      prepare_images(dir / "photos", dir / "staged", SfmOptions{}, null_reporter(), dir / "thumbs");
  ASSERT_EQ(inputs.videos.size(), 1u);
  const VideoClipSummary& clip = inputs.videos[0];
  EXPECT_EQ(clip.selection.frames_read, 70);
  EXPECT_EQ(clip.name, "walk.avi");
  ASSERT_EQ(inputs.images.size(), clip.selection.kept.size());
  EXPECT_GE(inputs.images.size(), 13u);
  EXPECT_TRUE(inputs.same_camera());
  for (const StagedImage& image : inputs.images) {
    EXPECT_EQ(image.video_clip, "walk.avi");
    EXPECT_EQ(image.width, kFrameWidth);
    EXPECT_TRUE(fs::exists(dir / "staged" / image.name)) << image.name;
    EXPECT_TRUE(fs::exists(dir / "thumbs" / (image.name + ".jpg"))) << image.name;
  }
  EXPECT_EQ(inputs.images.front().name, "walk.avi_f00000.jpg");
  // Only the kept frames were staged.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir / "staged"), fs::directory_iterator()),
            static_cast<std::ptrdiff_t>(inputs.images.size()));
  EXPECT_THAT(describe_selection(clip), HasSubstr("walk.avi: kept "));
  EXPECT_THAT(describe_selection(clip), HasSubstr("of 70 frames"));
}

TEST(VideoFrames, ASingleClipStandsForTheFolder) {
  hos::testing::TempDir dir;
  const fs::path clip = write_clip(dir / "clip.avi", render(still_then_moving()));
  SfmOptions options;
  options.video_max_frames = 5;
  const ImageInputs inputs = prepare_images(clip, dir / "staged", options, null_reporter());
  ASSERT_EQ(inputs.images.size(), 5u);
  EXPECT_GT(inputs.videos.at(0).selection.over_limit, 0);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir / "staged"), fs::directory_iterator()), 5);
}

TEST(VideoFrames, AnUnreadableClipIsSkippedWithTheReason) {
  hos::testing::TempDir dir;
  fs::create_directories(dir / "photos");
  write_bytes(dir / "photos" / "broken.mp4", std::string("\0\0\0\x18", 4) + "ftypisom" + std::string(100, '\x55'));
  for (const char* name : {"p0.jpg", "p1.jpg", "p2.jpg"}) {
    cv::imwrite((dir / "photos" / name).string(), texture_strip(kFrameWidth));
  }
  const ImageInputs inputs = prepare_images(dir / "photos", dir / "staged", SfmOptions{}, null_reporter());
  EXPECT_EQ(inputs.images.size(), 3u);
  ASSERT_EQ(inputs.skipped.size(), 1u);
  EXPECT_EQ(inputs.skipped[0].file.filename(), "broken.mp4");
  EXPECT_THAT(inputs.skipped[0].reason, HasSubstr("video"));
}

}  // namespace
}  // namespace hos::sfm

namespace hos::sfm {
namespace {

std::vector<StagedImage> frames_of(const std::string& clip, int count, int width = 640) {
  std::vector<StagedImage> images;
  for (int i = 0; i < count; ++i) {
    StagedImage image;
    image.name = video_frame_name(clip, 3 * i);
    image.width = width;
    image.height = 480;
    image.video_clip = clip;
    images.push_back(image);
  }
  return images;
}

TEST(VideoFramesPlan, EachClipIsItsOwnCameraApartFromPhotosOfTheSameSize) {
  std::vector<StagedImage> images = frames_of("a.mp4", 5);
  const std::vector<StagedImage> b = frames_of("b.mp4", 4);
  images.insert(images.end(), b.begin(), b.end());
  StagedImage photo;
  photo.name = "photo.jpg";
  photo.width = 640;
  photo.height = 480;
  images.push_back(photo);
  const std::vector<CameraGroup> groups = camera_groups(images, "auto");
  ASSERT_EQ(groups.size(), 3u);
  EXPECT_EQ(groups[0].video_clip, "a.mp4");
  EXPECT_EQ(groups[0].names.size(), 5u);
  EXPECT_EQ(groups[1].video_clip, "b.mp4");
  EXPECT_EQ(groups[1].names.size(), 4u);
  EXPECT_EQ(groups[2].video_clip, "");
  EXPECT_THAT(groups[0].describe(), HasSubstr("frames of a.mp4"));
}

TEST(VideoFramesPlan, ManyVideoFramesAreMatchedSequentiallyWithLoopDetection) {
  SfmOptions options;
  const PhotoSetFacts facts = photo_set_facts(frames_of("clip.mp4", 80), options.camera_mode);
  EXPECT_EQ(facts.video_frames, 80);
  const SfmPlan plan = plan_sfm(facts, options);
  EXPECT_EQ(plan.matcher, "sequential");
  EXPECT_TRUE(plan.loop_detection);
  EXPECT_GT(plan.vocab_tree_words, 0);
  ColmapRunContext context;
  context.vocab_tree = "ws/vocab_tree.bin";
  const std::vector<ColmapStep> steps = matching_steps(context, plan, options);
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_EQ(steps[0].command, "vocab_tree_builder");
  EXPECT_EQ(steps[1].command, "sequential_matcher");
  const auto& args = steps[1].args;
  const auto loop = std::find(args.begin(), args.end(), "--SequentialMatching.loop_detection");
  ASSERT_NE(loop, args.end());
  EXPECT_EQ(*(loop + 1), "1");
  const auto tree = std::find(args.begin(), args.end(), "--SequentialMatching.vocab_tree_path");
  ASSERT_NE(tree, args.end());
  EXPECT_EQ(*(tree + 1), "ws/vocab_tree.bin");
}

TEST(VideoFramesPlan, FewFramesOrPhotosAmongThemKeepTheUsualMatcher) {
  SfmOptions options;
  EXPECT_EQ(plan_sfm(photo_set_facts(frames_of("clip.mp4", 20), options.camera_mode), options).matcher, "exhaustive");
  std::vector<StagedImage> images = frames_of("clip.mp4", 80);
  StagedImage photo;
  photo.name = "photo.jpg";
  photo.width = 640;
  photo.height = 480;
  images.push_back(photo);
  const SfmPlan plan = plan_sfm(photo_set_facts(images, options.camera_mode), options);
  EXPECT_EQ(plan.matcher, "vocab_tree");
  EXPECT_FALSE(plan.loop_detection);
}

}  // namespace
}  // namespace hos::sfm
