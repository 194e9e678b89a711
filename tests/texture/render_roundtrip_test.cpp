// Texturing against the project's renderer (render/rasterizer.h): photos of a
// shaded sphere with a procedural albedo rendered by render::render_view, texture the
// exact mesh with the exact cameras, re-render the textured mesh from held-out
// cameras and compare with the renderer's own images of those cameras.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "render/rasterizer.h"
#include "synth/shapes.h"
#include "tests/support/textured_render.h"
#include "tests/texture/scene_fixtures.h"
#include "texture/texture_mesh.h"

namespace hos::texture {
namespace {

render::RenderObject truth_object(const TriangleMesh& mesh) {
  render::RenderObject object;
  object.mesh = mesh;
  object.material.procedural = [](const Eigen::Vector3f& x) { return testing::sphere_albedo(x); };
  return object;
}

TextureView rendered_view(const std::vector<render::RenderObject>& scene,
                          double azimuth,
                          double elevation,
                          const render::RenderOptions& options) {
  TextureView view = testing::make_view("view", azimuth, elevation, 3.5);
  view.image = render::render_view(scene, view.camera, view.pose, options).color;
  return view;
}

TEST(RenderRoundTrip, HeldOutViewsOfTheRendererMatch) {
  const TriangleMesh mesh = synth::icosphere(4, 1.0);
  const std::vector<render::RenderObject> truth = {truth_object(mesh)};
  render::RenderOptions options;  // shaded, light fixed in the world: bakeable
  std::vector<TextureView> views;
  views.reserve(12);
  for (int i = 0; i < 12; ++i) {
    views.push_back(rendered_view(truth, 30.0 * i + 5.0, i % 2 ? 35.0 : -30.0, options));
  }
  const TextureResult result = texture_mesh(mesh, views, TextureOptions{}, null_reporter());
  const std::vector<render::RenderObject> textured = {hos::testing::as_render_object(result.mesh)};
  render::RenderOptions unlit = options;
  unlit.lighting.unlit = true;  // the texture already holds the shaded colour
  for (const auto& [azimuth, elevation] : {std::pair{20.0, 10.0}, {200.0, -20.0}, {110.0, 60.0}}) {
    const TextureView held_out = rendered_view(truth, azimuth, elevation, options);
    const TextureView view = testing::make_view("view", azimuth, elevation, 3.5);
    const render::RenderedView again = render::render_view(textured, view.camera, view.pose, unlit);
    cv::Mat inner;
    cv::erode(again.mask, inner, cv::Mat::ones(5, 5, CV_8U));
    ASSERT_GT(cv::countNonZero(inner), 5000);
    cv::Mat a, b;
    again.color.convertTo(a, CV_32FC3);
    held_out.image.convertTo(b, CV_32FC3);
    cv::Mat diff = a - b;
    diff = diff.mul(diff);
    const cv::Scalar sse = cv::sum(diff.setTo(cv::Scalar::all(0), inner == 0));
    const double mse = (sse[0] + sse[1] + sse[2]) / (3.0 * cv::countNonZero(inner));
    const double psnr = 10.0 * std::log10(255.0 * 255.0 / mse);
    std::cout << "[ figures  ] renderer held-out az " << azimuth << " el " << elevation << ": PSNR over the object "
              << psnr << " dB\n";
    EXPECT_GT(psnr, 28.0);
  }
}

}  // namespace
}  // namespace hos::texture
