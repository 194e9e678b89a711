// The synthetic video: a readable clip of the frames' true cameras, named
// as the sfm stage stages them, moving smoothly around the scene.
#include "synth/video.h"

#include <gtest/gtest.h>

#include <opencv2/videoio.hpp>

#include "core/colmap_io.h"
#include "core/error.h"
#include "tests/support/test_support.h"

namespace hos::synth {
namespace {
namespace fs = std::filesystem;

DatasetOptions small_dataset() {
  DatasetOptions o;
  o.width = 160;
  o.height = 120;
  o.supersampling = 1;
  return o;
}

TEST(SynthVideo, CamerasCircleTheSceneSmoothlyAndAreNamedLikeStagedFrames) {
  const Scene scene = make_scene(SceneOptions{});
  VideoOptions video;
  video.frames = 60;
  const SparseModel model = make_video_cameras(scene, small_dataset(), video);
  ASSERT_EQ(model.images.size(), 60u);
  EXPECT_EQ(model.images.at(1).name, "clip.mp4_f00000.jpg");
  EXPECT_EQ(model.images.at(60).name, "clip.mp4_f00059.jpg");
  // Neighbouring frames are close; the first and the middle frame are
  // on opposite sides of the scene.
  const Eigen::Vector3d centre = scene.centre.cast<double>();
  double largest_step = 0.0;
  for (int id = 2; id <= 60; ++id) {
    largest_step = std::max(largest_step, (model.images.at(id).center() - model.images.at(id - 1).center()).norm());
  }
  const double radius = (model.images.at(1).center() - centre).norm();
  EXPECT_LT(largest_step, 0.2 * radius);
  EXPECT_LT((model.images.at(1).center() - centre).dot(model.images.at(31).center() - centre), 0.0);
}

TEST(SynthVideo, WritesAClipOpenCvReadsBackWithItsCameras) {
  hos::testing::TempDir dir;
  const Scene scene = make_scene(SceneOptions{});
  VideoOptions video;
  video.frames = 12;
  write_video(dir / "video", scene, small_dataset(), video);
  cv::VideoCapture capture((dir / "video" / "clip.mp4").string(), cv::CAP_FFMPEG);
  ASSERT_TRUE(capture.isOpened());
  int frames = 0;
  cv::Mat frame;
  while (capture.read(frame)) {
    EXPECT_EQ(frame.cols, 160);
    EXPECT_EQ(frame.rows, 120);
    ++frames;
  }
  EXPECT_EQ(frames, 12);
  EXPECT_EQ(read_colmap_model(dir / "video" / "sparse").images.size(), 12u);
}

TEST(SynthVideo, RefusesAPathOrAnUnknownContainer) {
  VideoOptions video;
  video.name = "sub/clip.mp4";
  EXPECT_THROW(video.validate(), ConfigError);
  video.name = "clip.gif";
  EXPECT_THROW(video.validate(), ConfigError);
  video.name = "clip.avi";
  video.frames = 2;
  EXPECT_THROW(video.validate(), ConfigError);
}

}  // namespace
}  // namespace hos::synth
