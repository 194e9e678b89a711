#include "refine/views.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/image_mask.h"
#include "render/depth_buffer.h"

namespace hos::refine {

std::optional<Eigen::Vector3d> RefineView::project(const Eigen::Vector3d& x_in_world, int level) const {
  const Eigen::Vector3d x = rotation * x_in_world + pose.cam_from_world_translation;
  if (x.z() <= 0.0) return std::nullopt;
  const double scale = 1.0 / static_cast<double>(1 << level);
  const double u = (camera.focal_x() * x.x() / x.z() + camera.principal_x()) * scale;
  const double v = (camera.focal_y() * x.y() / x.z() + camera.principal_y()) * scale;
  return Eigen::Vector3d(u, v, x.z());
}

namespace {

// The view's masks per pyramid level: a level's pixel is masked when any of
// the photo's pixels it averages is (a 2x2 box average is kUsable only when
// all four are), then grown for bilinear sampling.
std::vector<cv::Mat> mask_pyramid(const cv::Mat& mask, const std::vector<cv::Mat>& pyramid) {
  if (mask.empty()) return {};
  std::vector<cv::Mat> unmasked{mask};
  for (std::size_t l = 1; l < pyramid.size(); ++l) {
    cv::Mat averaged;
    cv::resize(unmasked.back(), averaged, pyramid[l].size(), 0, 0, cv::INTER_AREA);
    unmasked.push_back(averaged == kUsable);
  }
  std::vector<cv::Mat> masks;
  masks.reserve(unmasked.size());
  for (const cv::Mat& m : unmasked) masks.push_back(grow_masked_region(m));
  return masks;
}

}  // namespace

RefineView make_view(const Camera& camera,
                     const ImageRecord& pose,
                     const cv::Mat& photo,
                     int levels,
                     const std::string& source,
                     const cv::Mat& mask) {
  if (photo.cols != camera.width || photo.rows != camera.height) {
    throw InputError(source, "image is " + std::to_string(photo.cols) + "x" + std::to_string(photo.rows) +
                                 " but its camera is " + std::to_string(camera.width) + "x" +
                                 std::to_string(camera.height));
  }
  RefineView view;
  view.camera = camera;
  view.pose = pose;
  view.rotation = pose.rotation();
  view.center = pose.center();
  // Step 1: grey levels; ZNCC removes each view's gain and offset. 16 bits
  // hold the photo's 8 exactly and the box averages of the coarser levels to
  // 1/65535, at half the memory of floats.
  cv::Mat grey;
  if (photo.channels() == 3) {
    cv::cvtColor(photo, grey, cv::COLOR_BGR2GRAY);
  } else {
    grey = photo;
  }
  cv::Mat level0;
  grey.convertTo(level0, CV_16U, 257.0);
  // Step 2: 2x2 box averages, so a level's pixel centre is the mean of its
  // four parents and x_l = x_0 / 2^l holds exactly.
  view.pyramid.push_back(level0);
  for (int l = 1; l < levels; ++l) {
    const cv::Mat& previous = view.pyramid.back();
    cv::Mat next;
    cv::resize(previous, next, cv::Size(std::max(1, previous.cols / 2), std::max(1, previous.rows / 2)), 0, 0,
               cv::INTER_AREA);
    view.pyramid.push_back(next);
  }
  view.masks = mask_pyramid(mask, view.pyramid);
  return view;
}

std::vector<RefineView> load_views(const UndistortedWorkspace& workspace, int levels, Reporter& reporter) {
  std::vector<RefineView> views;
  for (const auto& [id, image] : workspace.model.images) {
    reporter.throw_if_cancelled();
    const std::string path = workspace.image_path(image).string();
    const cv::Mat photo = cv::imread(path, cv::IMREAD_COLOR);
    if (photo.empty()) throw InputError(path, "cannot be read as an image");
    views.push_back(
        make_view(workspace.model.camera_of(image), image, photo, levels, path, load_workspace_mask(workspace, image)));
  }
  return views;
}

void render_depths(const TriangleMesh& mesh, std::vector<RefineView>& views, int level) {
#pragma omp parallel for schedule(dynamic)
  for (int i = 0; i < static_cast<int>(views.size()); ++i) {
    RefineView& view = views[i];
    std::vector<Eigen::Vector3f> projected(mesh.vertices.size());
    for (std::size_t v = 0; v < projected.size(); ++v) {
      // Behind the camera: a z the rasterizer skips.
      projected[v] =
          view.project(mesh.vertices[v].cast<double>(), level).value_or(Eigen::Vector3d(0.0, 0.0, -1.0)).cast<float>();
    }
    const cv::Mat& image = view.pyramid[level];
    view.depth = render::rasterize_depth(mesh, projected, image.cols, image.rows).depth;
    view.depth_level = level;
  }
}

std::vector<float> pixel_footprints(const TriangleMesh& mesh,
                                    const std::vector<Eigen::Vector3f>& normals,
                                    const std::vector<RefineView>& views,
                                    double max_incidence_deg) {
  const double min_cos = std::cos(max_incidence_deg * M_PI / 180.0);
  std::vector<float> footprint(mesh.vertices.size(), std::numeric_limits<float>::infinity());
#pragma omp parallel for schedule(static)
  for (int v = 0; v < static_cast<int>(mesh.vertices.size()); ++v) {
    const Eigen::Vector3d x = mesh.vertices[v].cast<double>();
    for (const RefineView& view : views) {
      const std::optional<Eigen::Vector3d> p = view.project(x, 0);
      if (!p || p->x() < 0.0 || p->y() < 0.0 || p->x() > view.camera.width || p->y() > view.camera.height) continue;
      if (normals[v].cast<double>().dot((view.center - x).normalized()) < min_cos) continue;
      footprint[v] = std::min(footprint[v], static_cast<float>(p->z() / view.camera.focal_x()));
    }
  }
  return footprint;
}

bool sees(const RefineView& view, const Eigen::Vector3d& x_in_world, double tolerance) {
  const std::optional<Eigen::Vector3d> p = view.project(x_in_world, view.depth_level);
  if (!p) return false;
  const int cx = static_cast<int>(std::floor(p->x())), cy = static_cast<int>(std::floor(p->y()));
  if (cx < 0 || cy < 0 || cx >= view.depth.cols || cy >= view.depth.rows) return false;
  float nearest = std::numeric_limits<float>::max();
  for (int y = std::max(0, cy - 1); y <= std::min(view.depth.rows - 1, cy + 1); ++y) {
    for (int x = std::max(0, cx - 1); x <= std::min(view.depth.cols - 1, cx + 1); ++x) {
      nearest = std::min(nearest, view.depth.at<float>(y, x));
    }
  }
  return p->z() <= nearest + tolerance;
}

std::optional<Eigen::Vector3d> surface_point(const RefineView& view,
                                             const Eigen::Vector2d& pixel,
                                             double max_depth_jump) {
  const double x = pixel.x() - 0.5, y = pixel.y() - 0.5;
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= view.depth.cols || y0 + 1 >= view.depth.rows) return std::nullopt;
  const float d00 = view.depth.at<float>(y0, x0), d01 = view.depth.at<float>(y0, x0 + 1);
  const float d10 = view.depth.at<float>(y0 + 1, x0), d11 = view.depth.at<float>(y0 + 1, x0 + 1);
  const float lo = std::min({d00, d01, d10, d11}), hi = std::max({d00, d01, d10, d11});
  if (!std::isfinite(hi) || hi - lo > max_depth_jump) return std::nullopt;
  const double fx = x - x0, fy = y - y0;
  const double z = (1 - fy) * ((1 - fx) * d00 + fx * d01) + fy * ((1 - fx) * d10 + fx * d11);
  const double scale = static_cast<double>(1 << view.depth_level);
  const Eigen::Vector3d ray((pixel.x() * scale - view.camera.principal_x()) / view.camera.focal_x(),
                            (pixel.y() * scale - view.camera.principal_y()) / view.camera.focal_y(), 1.0);
  return view.pose.world_from_cam(z * ray);
}

std::optional<float> sample(const RefineView& view, int level, const Eigen::Vector2d& pixel) {
  const cv::Mat& image = view.pyramid[level];
  // COLMAP's pixel centres sit at +0.5.
  const double x = pixel.x() - 0.5, y = pixel.y() - 0.5;
  if (!(x >= 0.0 && y >= 0.0 && x <= image.cols - 1.0 && y <= image.rows - 1.0)) return std::nullopt;
  const int x0 = std::min(static_cast<int>(x), image.cols - 2), y0 = std::min(static_cast<int>(y), image.rows - 2);
  if (!usable_sample(view, level, x0, y0)) return std::nullopt;
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  const std::uint16_t* row0 = image.ptr<std::uint16_t>(y0);
  const std::uint16_t* row1 = image.ptr<std::uint16_t>(y0 + 1);
  const float top = row0[x0] + fx * (static_cast<float>(row0[x0 + 1]) - row0[x0]);
  const float bottom = row1[x0] + fx * (static_cast<float>(row1[x0 + 1]) - row1[x0]);
  return (top + fy * (bottom - top)) * (1.0f / 65535.0f);
}

}  // namespace hos::refine
