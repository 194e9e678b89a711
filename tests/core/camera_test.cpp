// core/camera.*: projection round trips for every COLMAP model hos supports.
#include "core/camera.h"

#include <gtest/gtest.h>

namespace hos {
namespace {

Camera make(CameraModel model, std::vector<double> params) {
  Camera c;
  c.model = model;
  c.width = 640;
  c.height = 480;
  c.params = std::move(params);
  return c;
}

std::vector<Camera> all_models() {
  return {make(CameraModel::kSimplePinhole, {500, 320, 240}), make(CameraModel::kPinhole, {500, 510, 321, 239}),
          make(CameraModel::kSimpleRadial, {500, 320, 240, -0.08}),
          make(CameraModel::kRadial, {500, 320, 240, -0.08, 0.01}),
          make(CameraModel::kOpenCV, {500, 505, 320, 240, -0.1, 0.02, 0.001, -0.002})};
}

TEST(Camera, ProjectUnprojectRoundTripForEveryModel) {
  for (const Camera& camera : all_models()) {
    SCOPED_TRACE(camera_model_name(camera.model));
    EXPECT_EQ(static_cast<int>(camera.params.size()), camera_model_num_params(camera.model));
    for (double x : {-0.5, 0.0, 0.3}) {
      for (double y : {-0.4, 0.1, 0.35}) {
        const Eigen::Vector3d p(x * 3.0, y * 3.0, 3.0);
        const auto pixel = camera.project(p);
        ASSERT_TRUE(pixel.has_value());
        const Eigen::Vector3d ray = camera.unproject(*pixel);
        EXPECT_NEAR(ray.x(), x, 1e-9);
        EXPECT_NEAR(ray.y(), y, 1e-9);
        EXPECT_DOUBLE_EQ(ray.z(), 1.0);
      }
    }
    EXPECT_FALSE(camera.project(Eigen::Vector3d(0, 0, -1)).has_value());
  }
}

TEST(Camera, PinholeProjectionFollowsColmapPixelConvention) {
  const Camera c = Camera::pinhole(1, 640, 480, 500, 500, 320, 240);
  const auto centre = c.project(Eigen::Vector3d(0, 0, 2));
  EXPECT_NEAR(centre->x(), 320, 1e-12);
  const auto p = c.project(Eigen::Vector3d(1, -0.5, 2));
  EXPECT_NEAR(p->x(), 320 + 250, 1e-9);
  EXPECT_NEAR(p->y(), 240 - 125, 1e-9);
  EXPECT_FALSE(c.has_distortion());
  EXPECT_TRUE(all_models()[4].has_distortion());
}

TEST(Camera, ModelNamesAndIdsMatchColmap) {
  EXPECT_EQ(camera_model_from_name("OPENCV"), CameraModel::kOpenCV);
  EXPECT_EQ(camera_model_from_id(2), CameraModel::kSimpleRadial);
  EXPECT_EQ(camera_model_name(CameraModel::kRadial), "RADIAL");
  EXPECT_THROW(camera_model_from_name("FISHEYE"), std::invalid_argument);
  EXPECT_THROW(camera_model_from_id(9), std::invalid_argument);
}

}  // namespace
}  // namespace hos
