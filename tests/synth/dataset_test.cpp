// A written dataset loads with the project's readers and agrees with itself:
// ground-truth vertices land on the rendered surface, sparse points reproject
// onto their keypoints, the images have texture, rendering is deterministic.
#include "synth/dataset.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/colmap_io.h"
#include "core/error.h"
#include "core/ply_io.h"
#include "core/undistorted_workspace.h"
#include "tests/support/test_support.h"

namespace hos::synth {
namespace {
namespace fs = std::filesystem;

DatasetOptions small_options() {
  DatasetOptions o;
  o.num_views = 8;
  o.width = 320;
  o.height = 240;
  o.write_depth = true;
  o.holdout = 2;
  o.num_points = 500;
  return o;
}

class DatasetTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new hos::testing::TempDir("hos-synth-test");
    scene_options_ = {5, "default", true};
    write_dataset(dir_->path() / "scene", make_scene(scene_options_), scene_options_, small_options());
  }
  static void TearDownTestSuite() { delete dir_; }
  static fs::path root() { return dir_->path() / "scene"; }
  static hos::testing::TempDir* dir_;
  static SceneOptions scene_options_;
};
hos::testing::TempDir* DatasetTest::dir_ = nullptr;
SceneOptions DatasetTest::scene_options_;

TEST_F(DatasetTest, LoadsWithTheProjectsReaders) {
  const UndistortedWorkspace ws = load_undistorted_workspace(root());
  EXPECT_EQ(ws.model.images.size(), 8u);
  ASSERT_EQ(ws.model.cameras.size(), 1u);
  const Camera& camera = ws.model.cameras.begin()->second;
  EXPECT_EQ(camera.model, CameraModel::kPinhole);
  EXPECT_EQ(camera.width, 320);
  EXPECT_NEAR(camera.focal_x(), 0.9 * 320, 1e-9);
  const SparseModel holdout = read_colmap_model(root() / "holdout" / "sparse");
  EXPECT_EQ(holdout.images.size(), 2u);
  for (const auto& [id, image] : holdout.images) {
    EXPECT_TRUE(fs::exists(root() / "holdout" / "images" / image.name));
    EXPECT_FALSE(ws.model.find_image(image.name) && ws.model.find_image(image.name)->center().isApprox(image.center()));
  }
  const TriangleMesh all = read_mesh_ply(root() / "gt_mesh.ply");
  const TriangleMesh objects = read_mesh_ply(root() / "gt_objects.ply");
  EXPECT_GT(all.num_faces(), objects.num_faces());
  EXPECT_EQ(objects.colors.size(), objects.num_vertices());
  std::ifstream in(root() / "scene.json");
  const nlohmann::json json = nlohmann::json::parse(in);
  EXPECT_EQ(json.at("seed").get<int>(), 5);
  EXPECT_EQ(json.at("objects").size(), 4u);
  const BoundingBox box = bounding_box(objects.vertices);
  EXPECT_NEAR(json.at("diagonal").get<double>(), box.diagonal(), 1e-4);
}

TEST_F(DatasetTest, GroundTruthVerticesLandOnTheRenderedSurface) {
  const SparseModel model = read_colmap_model(root() / "sparse");
  const TriangleMesh mesh = read_mesh_ply(root() / "gt_objects.ply");
  const Camera& camera = model.cameras.begin()->second;
  std::size_t visible = 0, on_mask = 0, in_frame = 0, total = 0;
  for (const auto& [id, image] : model.images) {
    const cv::Mat depth = cv::imread((root() / "depth" / (fs::path(image.name).stem().string() + ".tiff")).string(),
                                     cv::IMREAD_UNCHANGED);
    ASSERT_EQ(depth.type(), CV_32F);
    ASSERT_EQ(mesh.normals.size(), mesh.vertices.size());
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
      const Eigen::Vector3f& v = mesh.vertices[i];
      ++total;
      const Eigen::Vector3d xc = image.cam_from_world(v.cast<double>());
      const auto p = camera.project(xc);
      if (!p || p->x() < 0 || p->y() < 0 || p->x() >= camera.width || p->y() >= camera.height) continue;
      ++in_frame;
      const float d = depth.at<float>(static_cast<int>(p->y()), static_cast<int>(p->x()));
      // Occluded: something nearer covers the pixel; grazing: at the silhouette.
      if (d > 0 && d < xc.z() * (1 - 0.01)) continue;
      const Eigen::Vector3d to_camera = (image.center() - v.cast<double>()).normalized();
      if (mesh.normals[i].cast<double>().dot(to_camera) < 0.2) continue;
      ++visible;
      on_mask += d > 0;
    }
  }
  std::cout << "[ figures  ] GT vertices facing the camera, not occluded: " << visible
            << ", on the rendered surface: " << on_mask << " (" << 100.0 * on_mask / std::max<std::size_t>(visible, 1)
            << "%)\n";
  // The objects are fully in frame in every view.
  EXPECT_EQ(in_frame, total);
  EXPECT_GT(visible, total / 6);
  EXPECT_GT(static_cast<double>(on_mask), 0.99 * visible) << on_mask << " of " << visible;
}

TEST_F(DatasetTest, SparsePointsReprojectOntoTheirKeypoints) {
  const SparseModel model = read_colmap_model(root() / "sparse");
  EXPECT_GE(model.points.size(), 400u);
  const Camera& camera = model.cameras.begin()->second;
  for (const auto& [id, point] : model.points) {
    ASSERT_GE(point.track.size(), 2u);
    for (const TrackElement& t : point.track) {
      const ImageRecord& image = model.images.at(t.image_id);
      const Keypoint& kp = image.keypoints.at(t.keypoint_index);
      EXPECT_EQ(kp.point3d_id, id);
      const auto p = camera.project(image.cam_from_world(point.xyz));
      ASSERT_TRUE(p.has_value());
      EXPECT_LT((*p - kp.xy).norm(), 1e-3);
    }
  }
}

TEST_F(DatasetTest, ImagesHaveTextureOnTheObjects) {
  const SparseModel model = read_colmap_model(root() / "sparse");
  const ImageRecord& image = model.images.begin()->second;
  const cv::Mat colour = cv::imread((root() / "images" / image.name).string());
  const cv::Mat depth =
      cv::imread((root() / "depth" / (fs::path(image.name).stem().string() + ".tiff")).string(), cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(colour.empty());
  cv::Mat grey, mask;
  cv::cvtColor(colour, grey, cv::COLOR_BGR2GRAY);
  mask = depth > 0;
  cv::erode(mask, mask, cv::Mat(), cv::Point(-1, -1), 3);  // away from silhouettes
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(grey, corners, 5000, 0.01, 3, mask);
  const double area = cv::countNonZero(mask);
  std::cout << "[ figures  ] " << corners.size() << " corners on " << area << " surface pixels\n";
  // At least one corner per 150 pixels of surface (a flat colour gives none).
  EXPECT_GT(corners.size(), area / 150) << "surface pixels " << area;
  cv::Mat gx, gy;
  cv::Sobel(grey, gx, CV_32F, 1, 0);
  cv::Sobel(grey, gy, CV_32F, 0, 1);
  const cv::Mat magnitude = gx.mul(gx) + gy.mul(gy);
  EXPECT_GT(std::sqrt(cv::mean(magnitude, mask)[0]), 20.0);
}

TEST(DatasetRenderTest, DeterministicPerSeedAndExposureGainsApply) {
  DatasetOptions o = small_options();
  o.num_views = 3;
  o.holdout = 0;
  o.num_points = 50;
  const Scene scene = make_scene({4, "rock", false});
  const RenderedDataset a = render_dataset(scene, o);
  const RenderedDataset b = render_dataset(make_scene({4, "rock", false}), o);
  ASSERT_EQ(a.views.size(), 3u);
  for (std::size_t k = 0; k < a.views.size(); ++k)
    EXPECT_EQ(cv::norm(a.views[k].color, b.views[k].color, cv::NORM_INF), 0.0);
  EXPECT_EQ(a.model.points.size(), b.model.points.size());
  const RenderedDataset c = render_dataset(make_scene({5, "rock", false}), o);
  EXPECT_GT(cv::norm(a.views[0].color, c.views[0].color, cv::NORM_L1), 0.0);
  o.exposure_gains = {1.0f, 1.5f, 0.5f};
  const RenderedDataset g = render_dataset(scene, o);
  EXPECT_EQ(cv::norm(a.views[0].color, g.views[0].color, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::mean(g.views[1].color)[0], cv::mean(a.views[1].color)[0] * 1.1);
  EXPECT_LT(cv::mean(g.views[2].color)[0], cv::mean(a.views[2].color)[0] * 0.9);
  o.exposure_gains = {1.0f};
  EXPECT_THROW(render_dataset(scene, o), ConfigError);
}

// The hanging lantern (a thin part): it is in the ground truth, rendered in
// every view (fully in frame), and seen against the other objects, so a
// reconstruction must separate it from a background behind it.
TEST(DatasetRenderTest, HangingLanternIsRenderedInFrontOfTheObjectsAndInTheGroundTruth) {
  SceneOptions scene_options{5, "default", false};
  scene_options.hanging_object = true;
  const Scene scene = make_scene(scene_options);
  const Scene plain = make_scene({5, "default", false});
  const auto it = std::find(scene.names.begin(), scene.names.end(), "lantern");
  ASSERT_NE(it, scene.names.end());
  const int lantern = static_cast<int>(it - scene.names.begin());
  const TriangleMesh& lantern_mesh = scene.objects[lantern].mesh;
  EXPECT_EQ(merged_mesh(scene, false).vertices.size(),
            merged_mesh(plain, false).vertices.size() + lantern_mesh.vertices.size());
  DatasetOptions o = small_options();
  o.num_views = 6;
  o.width = 640;
  o.height = 480;
  o.holdout = 0;
  o.num_points = 50;
  const RenderedDataset data = render_dataset(scene, o);
  int views_with_background_beside = 0, views_with_thin_parts = 0;
  for (const render::RenderedView& view : data.views) {
    int pixels = 0, beside_background = 0, thin_rows = 0;
    for (int y = 0; y < view.object_id.rows; ++y) {
      int in_row = 0;
      for (int x = 1; x + 1 < view.object_id.cols; ++x) {
        if (view.object_id.at<int>(y, x) != lantern) continue;
        ++pixels;
        ++in_row;
        for (const int dx : {-1, 1}) {
          const int other = view.object_id.at<int>(y, x + dx);
          if (other >= 0 && other != lantern && view.depth.at<float>(y, x + dx) > view.depth.at<float>(y, x))
            ++beside_background;
        }
      }
      thin_rows += in_row > 0 && in_row <= 6;
    }
    EXPECT_GT(pixels, 100);
    views_with_thin_parts += thin_rows > 15;
    views_with_background_beside += beside_background > 20;
  }
  EXPECT_GE(views_with_background_beside, 1);
  // Rows where only the pole and the wire are seen, a few pixels wide (some
  // views see the pole behind an object or end-on).
  EXPECT_GE(views_with_thin_parts, 3);
}

// --masked-views: the first views carry a magenta box and a mask that
// covers exactly it (and 2 pixels around); the other views neither.
TEST(DatasetMasks, MaskedViewsHaveAPaintedBoxAndAMaskOverIt) {
  hos::testing::TempDir dir;
  const SceneOptions scene_options{5, "default", true};
  DatasetOptions o;
  o.num_views = 4;
  o.width = 160;
  o.height = 120;
  o.num_points = 100;
  o.masked_views = 2;
  write_dataset(dir / "scene", make_scene(scene_options), scene_options, o);
  for (int v = 0; v < o.num_views; ++v) {
    SCOPED_TRACE(v);
    const std::string name = view_name(v, false);
    const cv::Mat photo = cv::imread((dir / "scene" / "images" / name).string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(photo.empty());
    cv::Mat magenta;
    cv::inRange(photo, cv::Scalar(250, 0, 250), cv::Scalar(255, 5, 255), magenta);
    const fs::path mask_path = dir / "scene" / "masks" / (name + ".png");
    if (v >= o.masked_views) {
      EXPECT_EQ(cv::countNonZero(magenta), 0);
      EXPECT_FALSE(fs::exists(mask_path));
      continue;
    }
    const cv::Mat mask = cv::imread(mask_path.string(), cv::IMREAD_GRAYSCALE);
    ASSERT_EQ(mask.size(), photo.size());
    EXPECT_EQ(cv::countNonZero(magenta), 32 * 60);  // a fifth of the width, half the height
    cv::Mat magenta_unmasked;
    cv::bitwise_and(magenta, mask, magenta_unmasked);
    EXPECT_EQ(cv::countNonZero(magenta_unmasked), 0) << "every painted pixel is masked";
    EXPECT_EQ(static_cast<int>(mask.total()) - cv::countNonZero(mask), 36 * 64);
  }
}

}  // namespace
}  // namespace hos::synth
