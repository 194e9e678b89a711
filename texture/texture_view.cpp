#include "texture/texture_view.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/image_mask.h"

namespace hos::texture {

Eigen::Vector3d TextureView::project(const Eigen::Vector3d& x_in_world) const {
  const Eigen::Vector3d x = pose.cam_from_world(x_in_world);
  const double inv_z = 1.0 / x.z();
  return {camera.focal_x() * x.x() * inv_z + camera.principal_x(),
          camera.focal_y() * x.y() * inv_z + camera.principal_y(), x.z()};
}

std::vector<TextureView> load_texture_views(const UndistortedWorkspace& workspace, Reporter& reporter) {
  return load_texture_views(workspace, reporter, ViewRange{0, static_cast<int>(workspace.model.images.size()) - 1});
}

std::vector<TextureView> load_texture_views(const UndistortedWorkspace& workspace,
                                            Reporter& reporter,
                                            const ViewRange& range) {
  const std::vector<bool> selected = range.selection(static_cast<int>(workspace.model.images.size()));
  std::vector<TextureView> views;
  reporter.begin("load images", range.count(static_cast<int>(selected.size())));
  std::size_t index = 0;
  for (const auto& [id, image] : workspace.model.images) {
    if (!selected[index++]) continue;
    reporter.throw_if_cancelled();
    TextureView view;
    view.name = image.name;
    view.camera = workspace.model.camera_of(image);
    view.pose = image;
    view.pose.keypoints.clear();
    const auto path = workspace.image_path(image);
    view.image = cv::imread(path.string(), cv::IMREAD_COLOR);
    if (view.image.empty()) throw InputError(path.string(), "cannot read the image");
    if (view.image.cols != view.camera.width || view.image.rows != view.camera.height) {
      throw InputError(path.string(),
                       format_message("image is ", view.image.cols, "x", view.image.rows, " but its camera is ",
                                      view.camera.width, "x", view.camera.height));
    }
    view.mask = grow_masked_region(load_workspace_mask(workspace, image));
    views.push_back(std::move(view));
    reporter.advance();
  }
  reporter.end();
  return views;
}

namespace {

struct BilinearTaps {
  int x0, x1, y0, y1;
  float wx, wy;
};

BilinearTaps taps(const cv::Mat& image, double x, double y) {
  // Continuous coordinate x covers pixel floor(x); its centre is at +0.5.
  const double px = std::clamp(x - 0.5, 0.0, static_cast<double>(image.cols - 1));
  const double py = std::clamp(y - 0.5, 0.0, static_cast<double>(image.rows - 1));
  BilinearTaps t;
  t.x0 = static_cast<int>(px);
  t.y0 = static_cast<int>(py);
  t.x1 = std::min(t.x0 + 1, image.cols - 1);
  t.y1 = std::min(t.y0 + 1, image.rows - 1);
  t.wx = static_cast<float>(px - t.x0);
  t.wy = static_cast<float>(py - t.y0);
  return t;
}

}  // namespace

Eigen::Vector3f sample_rgb(const cv::Mat& bgr, double x, double y) {
  const BilinearTaps t = taps(bgr, x, y);
  auto at = [&](int r, int c) {
    const cv::Vec3b& p = bgr.at<cv::Vec3b>(r, c);
    return Eigen::Vector3f(p[2], p[1], p[0]);
  };
  return (1 - t.wy) * ((1 - t.wx) * at(t.y0, t.x0) + t.wx * at(t.y0, t.x1)) +
         t.wy * ((1 - t.wx) * at(t.y1, t.x0) + t.wx * at(t.y1, t.x1));
}

float sample_float(const cv::Mat& image, double x, double y) {
  const BilinearTaps t = taps(image, x, y);
  return (1 - t.wy) * ((1 - t.wx) * image.at<float>(t.y0, t.x0) + t.wx * image.at<float>(t.y0, t.x1)) +
         t.wy * ((1 - t.wx) * image.at<float>(t.y1, t.x0) + t.wx * image.at<float>(t.y1, t.x1));
}

}  // namespace hos::texture
