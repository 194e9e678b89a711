// Placement of a model (texture/placement.h, up_direction.h,
// geo_alignment.h) on synthetic scenes with known truth: the ground-truth
// cameras and surface of hos-synth, whose world up is -y.
#include "texture/placement.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <random>

#include "core/error.h"
#include "synth/dataset.h"
#include "synth/geo_tags.h"
#include "synth/scene.h"
#include "tests/support/camera_poses.h"
#include "tests/support/damaged_file_checks.h"
#include "texture/gltf_writer.h"

namespace hos::texture {
namespace {

const Eigen::Vector3d kSceneUp(0, -1, 0);

double angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / std::numbers::pi;
}

// The angle of the rotation between two rotation matrices.
double rotation_angle_deg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180.0 / std::numbers::pi;
}

struct SynthScene {
  synth::Scene scene;
  std::vector<CameraPose> cameras;
  std::vector<Eigen::Vector3f> vertices;  // objects and ground
  std::vector<Eigen::Vector3f> objects;   // objects only
};

SynthScene make_synth_scene(double tilt_deg, bool ground_plane = true) {
  synth::SceneOptions scene_options;
  scene_options.ground_plane = ground_plane;
  SynthScene s;
  s.scene = synth::make_scene(scene_options);
  synth::DatasetOptions options;
  options.tilt_deg = tilt_deg;
  s.cameras = camera_poses(synth::make_cameras(s.scene, options));
  s.vertices = synth::merged_mesh(s.scene, ground_plane).vertices;
  s.objects = synth::merged_mesh(s.scene, false).vertices;
  return s;
}

// A camera at centre looking along forward with the given image-up hint.
CameraPose camera_at(const Eigen::Vector3d& centre, const Eigen::Vector3d& forward, const Eigen::Vector3d& up_hint) {
  CameraPose c;
  c.cam_from_world = hos::testing::cam_from_world_looking(forward, up_hint);
  c.centre = centre;
  return c;
}

// The true footprint centre and base of the objects (scene frame).
Eigen::Vector3d true_footing(const std::vector<Eigen::Vector3f>& objects) {
  Eigen::Vector3f lo = objects[0], hi = objects[0];
  for (const auto& v : objects) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  return {0.5 * (lo.x() + hi.x()), hi.y(), 0.5 * (lo.z() + hi.z())};  // up is -y: the base is the largest y
}

double size_of(const std::vector<Eigen::Vector3f>& objects) {
  Eigen::Vector3f lo = objects[0], hi = objects[0];
  for (const auto& v : objects) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  return double((hi - lo).norm());
}

Eigen::Vector3d transform(const Eigen::Matrix4d& m, const Eigen::Vector3d& x) {
  return m.topLeftCorner<3, 3>() * x + m.topRightCorner<3, 1>();
}

// The cameras of a 120-degree arc of the rings, as photos of a facade from
// the street: the mean camera up leans with their tilt there (on a full ring
// the leaning cancels).
std::vector<CameraPose> facade_arc(const std::vector<CameraPose>& cameras) {
  std::vector<CameraPose> arc;
  for (const CameraPose& c : cameras) {
    const Eigen::Vector3d forward = c.cam_from_world.row(2).transpose();
    if (Eigen::Vector2d(forward.x(), forward.z()).normalized().x() > 0.5) arc.push_back(c);
  }
  return arc;
}

TEST(UpDirection, GravityFromTiltedCamerasWithinOneDegree) {
  for (const double tilt : {-20.0, -10.0, 0.0, 15.0}) {
    const SynthScene s = make_synth_scene(tilt);
    for (const auto& cameras : {s.cameras, facade_arc(s.cameras)}) {
      const UpEstimate up = estimate_up(cameras, {});
      std::cout << "[ figures  ] tilt " << tilt << " deg, " << cameras.size() << " cameras: gravity "
                << angle_deg(up.up, kSceneUp) << " deg, mean up " << angle_deg(mean_camera_up(cameras), kSceneUp)
                << " deg off\n";
      EXPECT_EQ(up.method, UpMethod::kGravity);
      EXPECT_LT(angle_deg(up.up, kSceneUp), 1.0) << "tilt " << tilt;
    }
  }
  // The mean camera up of the arc leans with the tilt and the rings' elevation.
  EXPECT_GT(angle_deg(mean_camera_up(facade_arc(make_synth_scene(15.0).cameras)), kSceneUp), 10.0);
}

TEST(UpDirection, RandomRollAveragesOut) {
  SynthScene s = make_synth_scene(12.0);
  std::mt19937 rng(3);
  std::normal_distribution<double> roll(0.0, 2.0 * std::numbers::pi / 180.0);
  for (CameraPose& c : s.cameras) {
    c.cam_from_world = Eigen::AngleAxisd(roll(rng), Eigen::Vector3d::UnitZ()).toRotationMatrix() * c.cam_from_world;
  }
  const UpEstimate up = estimate_up(s.cameras, {});
  EXPECT_EQ(up.method, UpMethod::kGravity);
  EXPECT_LT(angle_deg(up.up, kSceneUp), 1.0);
}

TEST(UpDirection, NadirCamerasWithVariedHeadingsUseGravity) {
  std::vector<CameraPose> cameras;
  cameras.reserve(12);
  for (int i = 0; i < 12; ++i) {
    const double heading = 2 * std::numbers::pi * i / 12.0 + 0.3;
    const int row = i / 4;  // a 4 x 3 grid of positions
    cameras.push_back(camera_at(Eigen::Vector3d(i % 4, -10.0, row), -kSceneUp,
                                Eigen::Vector3d(std::cos(heading), 0, std::sin(heading))));
  }
  const UpEstimate up = estimate_up(cameras, {});
  EXPECT_EQ(up.method, UpMethod::kGravity);
  EXPECT_LT(angle_deg(up.up, kSceneUp), 0.01);  // the sign from the viewing direction
}

// Photos of a facade all taken facing it and looking up: their x axes are
// parallel, so gravity is undetermined about them; the ground decides.
TEST(UpDirection, ParallelCamerasFallBackToTheGroundPlane) {
  std::vector<CameraPose> cameras;
  cameras.reserve(8);
  const Eigen::Vector3d forward = Eigen::Vector3d(0, -std::sin(0.25), std::cos(0.25));  // 14 deg up
  for (int i = 0; i < 8; ++i) cameras.push_back(camera_at(Eigen::Vector3d(i - 4.0, -1.6, 0), forward, kSceneUp));
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < 60; ++i) {
    for (int k = 0; k < 40; ++k) {
      points.emplace_back(float(i) * 0.2f - 6.0f, 0.0f, float(k) * 0.2f + 2.0f);  // ground, y = 0
      points.emplace_back(float(i) * 0.2f - 6.0f, -float(k) * 0.25f, 10.0f);      // facade
    }
  }
  const UpEstimate up = estimate_up(cameras, points);
  EXPECT_EQ(up.method, UpMethod::kGroundPlane) << up.fallback_reason;
  EXPECT_LT(angle_deg(up.up, kSceneUp), 1.0);
  const UpEstimate without_points = estimate_up(cameras, {});
  EXPECT_EQ(without_points.method, UpMethod::kMeanCameraUp);
  EXPECT_FALSE(without_points.fallback_reason.empty());
}

TEST(Placement, StandsCentredOnTheGround) {
  for (const double tilt : {-15.0, 15.0}) {
    const SynthScene s = make_synth_scene(tilt, /*ground_plane=*/false);
    const Placement p = place_model(s.vertices, s.cameras);
    const Eigen::Matrix4d& m = p.root_matrix;
    const double size = size_of(s.objects);
    EXPECT_LT(angle_deg(m.topLeftCorner<3, 3>() * kSceneUp, Eigen::Vector3d::UnitY()), 1.0);
    const Eigen::Vector3d footing = transform(m, true_footing(s.objects));
    std::cout << "[ figures  ] tilt " << tilt << ": true footing at (" << footing.transpose() << "), size " << size
              << "\n";
    EXPECT_LT(std::abs(footing.y()), 0.02 * size);
    EXPECT_LT(std::hypot(footing.x(), footing.z()), 0.02 * size);
    EXPECT_FALSE(p.metric);
    EXPECT_EQ(p.units_text(), "units: arbitrary (COLMAP's), because: no GPS");
  }
}

TEST(Placement, StrayPiecesDoNotMoveTheOrigin) {
  SynthScene s = make_synth_scene(0.0, false);
  const Placement clean = place_model(s.vertices, s.cameras);
  const double size = size_of(s.objects);
  std::vector<Eigen::Vector3f> with_debris = s.vertices;
  for (int i = 0; i < 20; ++i) with_debris.emplace_back(5.0f * float(size), 3.0f * float(size), float(i) * 0.01f);
  const Placement debris = place_model(with_debris, s.cameras);
  const Eigen::Matrix4d moved = debris.root_matrix - clean.root_matrix;
  EXPECT_LT((moved.topRightCorner<3, 1>().norm()), 0.01 * size);
}

// GPS of every camera: the true centres placed on Earth.
std::vector<PhotoPosition> true_gps(const SynthScene& s, const GeoPosition& origin, double metres_per_unit) {
  std::vector<PhotoPosition> out;
  for (const CameraPose& c : s.cameras)
    out.push_back({c.name, synth::scene_gps_position(c.centre, origin, metres_per_unit)});
  return out;
}

// The placed frame's axes from the scene's: x east (scene x), y up (scene
// -y), z south (scene -z), times the scale.
Eigen::Matrix3d expected_rotation() {
  Eigen::Matrix3d r;
  r << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  return r;
}

TEST(Placement, GpsGivesMetresAndEastNorthUp) {
  const SynthScene s = make_synth_scene(15.0);
  const GeoPosition origin{46.52, 6.57, 420.0};
  const double metres_per_unit = 25.0;
  PlacementInput input;
  input.photo_positions = true_gps(s, origin, metres_per_unit);
  const Placement p = place_model(s.vertices, s.cameras, input);
  ASSERT_TRUE(p.metric) << p.units_reason;
  ASSERT_TRUE(p.gps);
  EXPECT_TRUE(p.gps->vertical_from_gps);
  EXPECT_EQ(p.up.method, UpMethod::kGps);
  EXPECT_NEAR(p.scale, metres_per_unit, 0.01 * metres_per_unit);
  const Eigen::Matrix3d rotation = p.root_matrix.topLeftCorner<3, 3>() / p.scale;
  EXPECT_LT(rotation_angle_deg(rotation, expected_rotation()), 1.0);
  // The geographic origin is where the placed origin is on Earth.
  ASSERT_TRUE(p.geo_origin);
  ASSERT_TRUE(p.geo_origin->altitude_m);
  const Eigen::Vector3d placed_origin_in_scene =
      p.root_matrix.topLeftCorner<3, 3>().inverse() * -p.root_matrix.topRightCorner<3, 1>();
  const Eigen::Vector3d expected = synth::enu_from_scene(placed_origin_in_scene, metres_per_unit);
  EXPECT_LT((EnuFrame(origin).enu_from_geodetic(*p.geo_origin) - expected).norm(), 0.01);
  EXPECT_EQ(p.units_text().rfind("units: metres from GPS (" + std::to_string(s.cameras.size()) + " photos", 0), 0u)
      << p.units_text();
}

TEST(Placement, NoisyGpsWithAnOutlierStillFits) {
  const SynthScene s = make_synth_scene(-12.0);
  const GeoPosition origin{-33.9, 151.2, 30.0};
  const double metres_per_unit = 40.0;
  std::vector<PhotoPosition> gps = true_gps(s, origin, metres_per_unit);
  std::mt19937 rng(5);
  std::normal_distribution<double> horizontal(0.0, 1.5e-5), vertical(0.0, 10.0);  // ~1.5 m, 10 m
  for (PhotoPosition& g : gps) {
    g.gps.latitude_deg += horizontal(rng);
    g.gps.longitude_deg += horizontal(rng);
    *g.gps.altitude_m += vertical(rng);
  }
  gps[3].gps.latitude_deg += 0.003;  // 330 m off
  PlacementInput input;
  input.photo_positions = gps;
  const Placement p = place_model(s.vertices, s.cameras, input);
  ASSERT_TRUE(p.metric) << p.units_reason;
  EXPECT_EQ(p.gps->inliers, static_cast<int>(s.cameras.size()) - 1);
  EXPECT_FALSE(p.gps->vertical_from_gps);  // 10 m altitude noise: gravity keeps the vertical
  EXPECT_EQ(p.up.method, UpMethod::kGravity);
  std::cout << "[ figures  ] noisy GPS: scale " << p.scale << " (true " << metres_per_unit << "), residual "
            << p.gps->rms_residual_m << " m, tilt uncertainty " << p.gps->tilt_uncertainty_deg << " deg\n";
  EXPECT_NEAR(p.scale, metres_per_unit, 0.01 * metres_per_unit);
  EXPECT_LT(rotation_angle_deg(p.root_matrix.topLeftCorner<3, 3>() / p.scale, expected_rotation()), 1.0);
}

TEST(Placement, GpsWithoutAltitudeFitsHorizontally) {
  const SynthScene s = make_synth_scene(10.0);
  std::vector<PhotoPosition> gps = true_gps(s, GeoPosition{51.5, -0.12, 0.0}, 30.0);
  for (PhotoPosition& g : gps) g.gps.altitude_m.reset();
  PlacementInput input;
  input.photo_positions = gps;
  const Placement p = place_model(s.vertices, s.cameras, input);
  ASSERT_TRUE(p.metric) << p.units_reason;
  EXPECT_FALSE(p.gps->vertical_from_gps);
  EXPECT_NEAR(p.scale, 30.0, 0.3);
  EXPECT_LT(rotation_angle_deg(p.root_matrix.topLeftCorner<3, 3>() / p.scale, expected_rotation()), 1.0);
  ASSERT_TRUE(p.geo_origin);
  EXPECT_FALSE(p.geo_origin->altitude_m);
}

TEST(Placement, SmallGpsSpreadLeavesArbitraryUnits) {
  const SynthScene s = make_synth_scene(0.0);
  PlacementInput input;
  input.photo_positions = true_gps(s, GeoPosition{10.0, 20.0, 5.0}, 1.0);  // a few metres across
  const Placement p = place_model(s.vertices, s.cameras, input);
  EXPECT_FALSE(p.metric);
  EXPECT_FALSE(p.geo_origin);
  EXPECT_EQ(p.units_text().rfind("units: arbitrary (COLMAP's), because: GPS spread ", 0), 0u) << p.units_text();
}

TEST(Placement, ScaleDistanceSetsMetres) {
  const SynthScene s = make_synth_scene(0.0);
  PlacementInput input;
  const double model_distance = (s.cameras[0].centre - s.cameras[5].centre).norm();
  input.scale_distance = ScaleDistance{s.cameras[0].name, s.cameras[5].name, 12.5};
  const Placement p = place_model(s.vertices, s.cameras, input);
  EXPECT_TRUE(p.metric);
  EXPECT_NEAR(p.scale, 12.5 / model_distance, 1e-9);
  const Eigen::Vector3d a = transform(p.root_matrix, s.cameras[0].centre);
  const Eigen::Vector3d b = transform(p.root_matrix, s.cameras[5].centre);
  EXPECT_NEAR((a - b).norm(), 12.5, 1e-6);
  input.scale_distance = ScaleDistance{s.cameras[0].name, "missing.jpg", 12.5};
  EXPECT_THROW(place_model(s.vertices, s.cameras, input), ConfigError);
  input.scale_distance = ScaleDistance{s.cameras[0].name, s.cameras[0].name, 12.5};
  EXPECT_THROW(place_model(s.vertices, s.cameras, input), ConfigError);
}

TEST(Placement, ParsesScaleDistance) {
  const ScaleDistance d = parse_scale_distance("IMG_1.jpg  IMG_7.jpg 12.5");
  EXPECT_EQ(d.photo_a, "IMG_1.jpg");
  EXPECT_EQ(d.photo_b, "IMG_7.jpg");
  EXPECT_DOUBLE_EQ(d.metres, 12.5);
  for (const char* bad : {"", "a.jpg b.jpg", "a.jpg b.jpg 12m", "a.jpg b.jpg -3", "a.jpg b.jpg 3 4"}) {
    EXPECT_THROW(parse_scale_distance(bad), ConfigError) << bad;
  }
}

TEST(Placement, GlbCarriesUnitsAndGeoOrigin) {
  TexturedMesh mesh;  // one textured triangle
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  mesh.uvs = {{0, 0}, {1, 0}, {0, 1}};
  mesh.indices = {{0, 1, 2}};
  mesh.atlases = {cv::Mat(4, 4, CV_8UC3, cv::Scalar(10, 20, 30))};
  mesh.metric = true;
  mesh.geo_origin = GeoPosition{46.5, 6.6, 401.5};
  const auto file = std::filesystem::temp_directory_path() / "hos_placement_test.glb";
  write_glb(file, mesh);
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &error, &warning, file.string())) << error;
  const tinygltf::Value& extras = model.asset.extras;
  EXPECT_EQ(extras.Get("units").Get<std::string>(), "metres");
  EXPECT_DOUBLE_EQ(extras.Get("geo_origin").Get("latitude_deg").GetNumberAsDouble(), 46.5);
  EXPECT_DOUBLE_EQ(extras.Get("geo_origin").Get("longitude_deg").GetNumberAsDouble(), 6.6);
  EXPECT_DOUBLE_EQ(extras.Get("geo_origin").Get("altitude_m").GetNumberAsDouble(), 401.5);
  mesh.metric = false;
  mesh.geo_origin.reset();
  write_glb(file, mesh);
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &error, &warning, file.string())) << error;
  EXPECT_EQ(model.asset.extras.Get("units").Get<std::string>(), "arbitrary");
  EXPECT_FALSE(model.asset.extras.Has("geo_origin"));
  std::filesystem::remove(file);
}

TEST(Placement, ApplyRootMatrixBakesTheTransform) {
  TexturedMesh mesh;
  mesh.positions = {{1, 2, 3}, {-1, 0, 4}};
  mesh.normals = {{0, 0, 1}, {1, 0, 0}};
  mesh.root_matrix.topLeftCorner<3, 3>() =
      2.0 * Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  mesh.root_matrix.topRightCorner<3, 1>() = Eigen::Vector3d(0.5, -1, 2);
  const Eigen::Matrix4d m = mesh.root_matrix;
  const std::vector<Eigen::Vector3f> before = mesh.positions;
  apply_root_matrix(mesh);
  EXPECT_TRUE(mesh.root_matrix.isIdentity());
  for (std::size_t i = 0; i < before.size(); ++i) {
    EXPECT_LT((mesh.positions[i].cast<double>() - transform(m, before[i].cast<double>())).norm(), 1e-5);
  }
  const Eigen::Vector3d rotated_z = (m.topLeftCorner<3, 3>() * Eigen::Vector3d::UnitZ()).normalized();
  EXPECT_LT((mesh.normals[0].cast<double>() - rotated_z).norm(), 1e-6);
}

TEST(GeoAlignment, ReadsPhotoPositions) {
  const auto file = std::filesystem::temp_directory_path() / "hos_placement_test_positions.json";
  {
    std::ofstream out(file);
    out << R"({"photos": [{"name": "a.jpg", "gps": {"latitude_deg": 46.5, "longitude_deg": 6.6, "altitude_m": 400}},
                          {"name": "b.jpg", "gps": null},
                          {"name": "c.jpg", "gps": {"latitude_deg": -1.5, "longitude_deg": 2}}]})";
  }
  const auto positions = read_photo_positions(file);
  ASSERT_EQ(positions.size(), 2u);
  EXPECT_EQ(positions[0].name, "a.jpg");
  EXPECT_DOUBLE_EQ(*positions[0].gps.altitude_m, 400.0);
  EXPECT_FALSE(positions[1].gps.altitude_m);
  {
    std::ofstream out(file);
    out << R"({"photos": [{"name": "a.jpg", "gps": {"latitude_deg": 95, "longitude_deg": 6.6}}]})";
  }
  EXPECT_THROW(read_photo_positions(file), InputError);
  std::filesystem::remove(file);
  EXPECT_THROW(read_photo_positions(file), InputError);
}

TEST(GeoAlignment, AMissingOrDamagedPositionsFileIsAnInputErrorNamingIt) {
  hos::testing::expect_input_error_naming_the_file(
      "report.json", [](const std::filesystem::path& file) { read_photo_positions(file); },
      {"", "[1, 2]", R"({"photos": 3})", R"({"photos": [{"gps": null}]})", R"({"photos": [{"name": 7}]})",
       R"({"photos": [{"name": "a.jpg", "gps": {"latitude_deg": 46.5}}]})",
       R"({"photos": [{"name": "a.jpg", "gps": {"latitude_deg": "N", "longitude_deg": 6.6}}]})",
       R"({"photos": [{"name": "a.jpg", "gps": {"latitude_deg": 46.5, "longitude_deg": 6.6, "altitude_m": "high"}}]})",
       R"({"photos": [{"name": "a.jpg", "gps": {"latitude_deg": -90.5, "longitude_deg": 6.6}}]})",
       R"({"photos": [{"name": "a.jpg", "gps": 46.5}]})"});
}

}  // namespace
}  // namespace hos::texture
