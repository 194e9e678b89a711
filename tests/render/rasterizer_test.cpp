// render_view against analytic ground truth: projected sphere area and depth,
// a tilted plane crossing the near plane (perspective-correct depth and
// clipping), texel placement of a UV texture, Lambertian shading values.
#include "render/rasterizer.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <random>

namespace hos::render {
namespace {

// A latitude-longitude sphere whose poles lie on the z axis, CCW from outside.
TriangleMesh uv_sphere(const Eigen::Vector3f& centre, float r, int rings, int segments) {
  TriangleMesh m;
  m.vertices.push_back(centre + Eigen::Vector3f(0, 0, -r));
  for (int i = 1; i < rings; ++i) {
    const float theta = static_cast<float>(std::numbers::pi) * i / rings;
    for (int j = 0; j < segments; ++j) {
      const float phi = 2 * static_cast<float>(std::numbers::pi) * j / segments;
      m.vertices.push_back(centre + r * Eigen::Vector3f(std::sin(theta) * std::cos(phi),
                                                        std::sin(theta) * std::sin(phi), -std::cos(theta)));
    }
  }
  m.vertices.push_back(centre + Eigen::Vector3f(0, 0, r));
  const int last = static_cast<int>(m.vertices.size()) - 1;
  auto id = [&](int ring, int j) { return 1 + (ring - 1) * segments + (j % segments); };
  for (int j = 0; j < segments; ++j) m.faces.emplace_back(0, id(1, j + 1), id(1, j));
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      m.faces.emplace_back(id(i, j), id(i, j + 1), id(i + 1, j + 1));
      m.faces.emplace_back(id(i, j), id(i + 1, j + 1), id(i + 1, j));
    }
  for (int j = 0; j < segments; ++j) m.faces.emplace_back(last, id(rings - 1, j), id(rings - 1, j + 1));
  return m;
}

TriangleMesh quad(const Eigen::Vector3f& a,
                  const Eigen::Vector3f& b,
                  const Eigen::Vector3f& c,
                  const Eigen::Vector3f& d) {
  TriangleMesh m;
  m.vertices = {a, b, c, d};
  m.faces = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

float srgb8_to_linear(int v) {
  const float c = v / 255.0f;
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

int linear_to_srgb8(float c) {
  c = std::clamp(c, 0.0f, 1.0f);
  const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
  return static_cast<int>(std::lround(255.0f * s));
}

const Camera kCamera = Camera::pinhole(1, 320, 240, 400, 400, 160, 120);
const ImageRecord kIdentityPose{};

TEST(RasterizerTest, SphereMaskAreaAndDepthMatchTheAnalyticProjection) {
  const float r = 1.0f, d = 6.0f;
  RenderObject sphere{uv_sphere({0, 0, d}, r, 96, 192), {}};
  const RenderedView view = render_view({sphere}, kCamera, kIdentityPose);
  // Silhouette of a sphere on the optical axis: a disk of radius f r / sqrt(d^2 - r^2).
  const double rho = 400.0 * r / std::sqrt(d * d - r * r);
  const double expected = std::numbers::pi * rho * rho;
  const double area = cv::countNonZero(view.mask);
  EXPECT_NEAR(area, expected, 0.01 * expected) << "rho " << rho;
  // Depth at the pixel next to the principal point: the sphere's nearest point.
  const float centre_depth = view.depth.at<float>(120, 160);
  EXPECT_NEAR(centre_depth, d - r, 1e-3);
  // Everywhere: depth of the sphere along the pixel's ray, within the
  // polygonal approximation (sagitta ~ r (pi/96)^2 / 8).
  double max_error = 0;
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 320; ++x) {
      if (!view.mask.at<std::uint8_t>(y, x)) continue;
      const Eigen::Vector3d ray((x + 0.5 - 160) / 400.0, (y + 0.5 - 120) / 400.0, 1.0);
      // |t ray - c|^2 = r^2, nearest root; z = t.
      const double a = ray.squaredNorm(), b = -2.0 * d, c = d * d - r * r;
      const double disc = b * b - 4 * a * c;
      if (disc < 0.05) continue;  // grazing rays at the silhouette
      const double t = (-b - std::sqrt(disc)) / (2 * a);
      max_error = std::max(max_error, std::abs(view.depth.at<float>(y, x) - t));
    }
  EXPECT_LT(max_error, 5e-3);
  // Mask, depth, ids and normals agree.
  for (int y = 0; y < 240; y += 7)
    for (int x = 0; x < 320; x += 7) {
      const bool on = view.mask.at<std::uint8_t>(y, x) != 0;
      EXPECT_EQ(on, view.depth.at<float>(y, x) > 0);
      EXPECT_EQ(on, view.face_id.at<int>(y, x) >= 0);
      EXPECT_EQ(on, view.object_id.at<int>(y, x) == 0);
      if (on) {
        const cv::Vec3f n = view.normal.at<cv::Vec3f>(y, x);
        EXPECT_NEAR(cv::norm(n), 1.0, 1e-4);
        EXPECT_LT(n[2], 0.0f);  // facing the camera
      }
    }
}

TEST(RasterizerTest, TiltedPlaneThroughTheNearPlaneHasPerspectiveCorrectDepth) {
  // The plane y = 1 (below the camera), extending far behind it, so its
  // triangles need near-plane clipping.
  RenderObject plane{quad({-50, 1, -50}, {-50, 1, 50}, {50, 1, 50}, {50, 1, -50}), {}};
  const RenderedView view = render_view({plane}, kCamera, kIdentityPose);
  int checked = 0;
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 320; ++x) {
      const double ray_y = (y + 0.5 - 120) / 400.0;
      const float depth = view.depth.at<float>(y, x);
      if (ray_y <= 0.0) {
        EXPECT_EQ(depth, 0.0f) << x << "," << y;  // above the horizon
        continue;
      }
      const double z = 1.0 / ray_y;  // ray (.., ray_y, 1) * z hits y = 1
      if (z > 49.0) continue;        // beyond the plane's far edge
      ASSERT_GT(depth, 0.0f) << x << "," << y;
      EXPECT_NEAR(depth, z, 1e-4 * z) << x << "," << y;
      ++checked;
    }
  EXPECT_GT(checked, 320 * 100);
}

TEST(RasterizerTest, TexturedQuadShowsTheExpectedTexels) {
  // 4x4 texels of distinct colours, each an 8x8 block so that bilinear
  // filtering inside a block returns the texel's colour exactly.
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> u(20, 235);
  cv::Mat small(4, 4, CV_8UC3);
  for (int i = 0; i < 16; ++i) small.at<cv::Vec3b>(i / 4, i % 4) = cv::Vec3b(u(rng), u(rng), u(rng));
  cv::Mat texture;
  cv::resize(small, texture, cv::Size(32, 32), 0, 0, cv::INTER_NEAREST);
  // A fronto-parallel quad at z = 4 covering x, y in [-1, 1]: image corners
  // (60, 20)..(260, 220). uv (0, 0) at its top-left (x = -1, y = -1).
  RenderObject obj;
  obj.mesh = quad({-1, -1, 4}, {-1, 1, 4}, {1, 1, 4}, {1, -1, 4});
  obj.material.textures = {texture};
  obj.material.corner_uvs = {{0, 0}, {0, 1}, {1, 1}, {0, 0}, {1, 1}, {1, 0}};
  RenderOptions options;
  options.lighting.unlit = true;
  const RenderedView view = render_view({obj}, kCamera, kIdentityPose, options);
  for (int ty = 0; ty < 4; ++ty)
    for (int tx = 0; tx < 4; ++tx) {
      const int px = 60 + 50 * tx + 25, py = 20 + 50 * ty + 25;  // texel centre in the image
      const cv::Vec3b got = view.color.at<cv::Vec3b>(py, px);
      const cv::Vec3b want = small.at<cv::Vec3b>(ty, tx);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 1) << "texel " << tx << "," << ty;
    }
  // Outside the quad: background.
  EXPECT_EQ(view.color.at<cv::Vec3b>(5, 5), cv::Vec3b(0, 0, 0));
  EXPECT_EQ(view.mask.at<std::uint8_t>(5, 5), 0);
}

TEST(RasterizerTest, LambertianShadingVertexColoursAndExposure) {
  // A quad facing the camera (normal -z); the light comes from -z rotated by 60 degrees.
  RenderObject obj;
  obj.mesh = quad({-1, -1, 4}, {-1, 1, 4}, {1, 1, 4}, {1, -1, 4});
  obj.mesh.colors.assign(4, Rgb8{200, 120, 40});
  RenderOptions options;
  options.supersampling = 3;
  options.lighting.direction_to_light =
      Eigen::Vector3f(std::sin(std::numbers::pi / 3), 0, -std::cos(std::numbers::pi / 3));
  for (const float gain : {1.0f, 1.3f}) {
    options.exposure_gain = gain;
    const RenderedView view = render_view({obj}, kCamera, kIdentityPose, options);
    const float shading = options.lighting.ambient + options.lighting.diffuse * 0.5f;
    const cv::Vec3b got = view.color.at<cv::Vec3b>(120, 160);
    const int want[3] = {40, 120, 200};  // BGR
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(got[c], linear_to_srgb8(gain * shading * srgb8_to_linear(want[c])), 1) << "gain " << gain;
  }
}

TEST(RasterizerTest, SupersamplingAntialiasesEdgesAndIsDeterministic) {
  RenderObject sphere{uv_sphere({0.13f, -0.07f, 5}, 1.0f, 48, 96), {}};
  sphere.material.constant_albedo = Eigen::Vector3f::Ones();
  RenderOptions options;
  options.lighting.unlit = true;
  options.supersampling = 4;
  const RenderedView a = render_view({sphere}, kCamera, kIdentityPose, options);
  const RenderedView b = render_view({sphere}, kCamera, kIdentityPose, options);
  EXPECT_EQ(cv::norm(a.color, b.color, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.depth, b.depth, cv::NORM_INF), 0.0);
  cv::Mat grey;
  cv::cvtColor(a.color, grey, cv::COLOR_BGR2GRAY);
  const int partial = cv::countNonZero((grey > 10) & (grey < 245));
  EXPECT_GT(partial, 100);  // the silhouette's perimeter is ~ 2 pi 80 px
  options.supersampling = 1;
  const RenderedView aliased = render_view({sphere}, kCamera, kIdentityPose, options);
  cv::cvtColor(aliased.color, grey, cv::COLOR_BGR2GRAY);
  EXPECT_EQ(cv::countNonZero((grey > 10) & (grey < 245)), 0);
}

TEST(RasterizerTest, SameResultWithOneOrTwoThreadsAndNonFiniteFacesAreSkipped) {
  RenderObject sphere{uv_sphere({0.2f, 0.1f, 4}, 1.0f, 48, 96), {}};
  sphere.material.procedural = [](const Eigen::Vector3f& x) {
    return Eigen::Vector3f(0.5f + 0.4f * std::sin(20 * x.x()), 0.5f + 0.4f * std::cos(17 * x.y()), 0.3f);
  };
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const RenderedView one = render_view({sphere}, kCamera, kIdentityPose);
  omp_set_num_threads(2);
  const RenderedView two = render_view({sphere}, kCamera, kIdentityPose);
  omp_set_num_threads(threads);
  EXPECT_EQ(cv::norm(one.color, two.color, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(one.depth, two.depth, cv::NORM_INF), 0.0);
  // A NaN vertex removes its faces and nothing else.
  RenderObject broken = sphere;
  broken.mesh.vertices[0].x() = std::numeric_limits<float>::quiet_NaN();
  const RenderedView with_nan = render_view({broken}, kCamera, kIdentityPose);
  EXPECT_TRUE(cv::checkRange(with_nan.depth));
  EXPECT_TRUE(cv::checkRange(with_nan.normal));
  // The pole's fan faces the camera: through the hole the far side shows.
  const int changed = cv::countNonZero(cv::abs(one.depth - with_nan.depth) > 1e-4);
  // The fan is a disk of radius ~ f sin(pi / 48) / 3 = 8.7 px: ~ 240 pixels.
  EXPECT_GT(changed, 180);
  EXPECT_LT(changed, 300);
  EXPECT_EQ(cv::countNonZero(one.mask), cv::countNonZero(with_nan.mask));
}

TEST(RasterizerTest, BadMaterialsAreRejected) {
  RenderObject obj;
  obj.mesh = quad({-1, -1, 4}, {-1, 1, 4}, {1, 1, 4}, {1, -1, 4});
  obj.material.textures = {cv::Mat(4, 4, CV_8UC3, cv::Scalar::all(0))};
  EXPECT_THROW(render_view({obj}, kCamera, kIdentityPose), std::invalid_argument);  // no uvs
}

}  // namespace
}  // namespace hos::render
