// The accuracy check on a hos-synth scene: texture the ground-truth
// mesh with the ground-truth cameras and photos, re-render it with the
// project's renderer from held-out cameras that were not used for texturing,
// and compare with the renderer's own images of those cameras over the object.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <opencv2/imgproc.hpp>

#include "render/rasterizer.h"
#include "synth/dataset.h"
#include "synth/scene.h"
#include "tests/support/textured_render.h"
#include "texture/texture_mesh.h"

namespace hos::texture {
namespace {

TEST(SynthScene, HeldOutViewsPsnrOnTheObject) {
  const synth::Scene scene = synth::make_scene(synth::SceneOptions{});
  synth::DatasetOptions options;
  options.num_views = 24;
  options.holdout = 3;
  const synth::RenderedDataset data = synth::render_dataset(scene, options);
  std::vector<TextureView> views;
  std::size_t k = 0;
  for (const auto& [id, image] : data.model.images) {
    TextureView view;
    view.name = image.name;
    view.camera = data.model.camera_of(image);
    view.pose = image;
    view.pose.keypoints.clear();
    view.image = data.views[k++].color;
    views.push_back(std::move(view));
  }
  const TriangleMesh mesh = synth::merged_mesh(scene, false);
  const TextureResult result = texture_mesh(mesh, views, TextureOptions{}, null_reporter());
  const std::vector<render::RenderObject> textured = {hos::testing::as_render_object(result.mesh)};
  render::RenderOptions unlit;
  unlit.lighting.unlit = true;  // the photos' shading is baked into the texture
  k = 0;
  for (const auto& [id, image] : data.holdout.images) {
    const render::RenderedView& truth = data.holdout_views[k++];
    const render::RenderedView again = render::render_view(textured, data.holdout.camera_of(image), image, unlit);
    cv::Mat both, inner;
    cv::bitwise_and(truth.mask, again.mask, both);
    cv::erode(both, inner, cv::Mat::ones(3, 3, CV_8U));
    ASSERT_GT(cv::countNonZero(inner), 2000);
    cv::Mat a, b;
    again.color.convertTo(a, CV_32FC3);
    truth.color.convertTo(b, CV_32FC3);
    cv::Mat diff = a - b;
    diff = diff.mul(diff);
    diff.setTo(cv::Scalar::all(0), inner == 0);
    const cv::Scalar sse = cv::sum(diff);
    const double mse = (sse[0] + sse[1] + sse[2]) / (3.0 * cv::countNonZero(inner));
    const double psnr = 10.0 * std::log10(255.0 * 255.0 / mse);
    std::cout << "[ figures  ] hos-synth held-out view " << image.name << ": PSNR over the object " << psnr << " dB ("
              << mesh.faces.size() << " faces, " << result.stats.num_unseen_faces << " unseen)\n";
    // Issue 6: at least 28 dB over the object.
    EXPECT_GT(psnr, 28.0);
  }
}

}  // namespace
}  // namespace hos::texture
