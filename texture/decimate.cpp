#include "texture/decimate.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace hos::texture {

std::vector<SamplingCamera> sampling_cameras(const std::vector<TextureView>& views) {
  std::vector<SamplingCamera> out;
  out.reserve(views.size());
  for (const TextureView& v : views) out.push_back({v.camera, v.pose});
  return out;
}

std::vector<SamplingCamera> sampling_cameras(const SparseModel& model) {
  std::vector<SamplingCamera> out;
  for (const auto& [id, image] : model.images) {
    SamplingCamera c{model.camera_of(image), image};
    c.pose.keypoints.clear();
    out.push_back(std::move(c));
  }
  return out;
}

double finest_pixel_size(const TriangleMesh& mesh, const std::vector<SamplingCamera>& cameras, double quantile) {
  constexpr std::size_t kMaxSamples = 200000;
  const std::size_t step = std::max<std::size_t>(1, mesh.vertices.size() / kMaxSamples);
  std::vector<double> sizes;
  for (std::size_t v = 0; v < mesh.vertices.size(); v += step) {
    const Eigen::Vector3d x = mesh.vertices[v].cast<double>();
    double finest = std::numeric_limits<double>::infinity();
    for (const SamplingCamera& c : cameras) {
      const Eigen::Vector3d in_cam = c.pose.cam_from_world(x);
      const auto pixel = c.camera.project(in_cam);
      if (!pixel || pixel->x() < 0 || pixel->y() < 0 || pixel->x() > c.camera.width || pixel->y() > c.camera.height) {
        continue;
      }
      finest = std::min(finest, in_cam.z() / std::max(c.camera.focal_x(), c.camera.focal_y()));
    }
    if (std::isfinite(finest)) sizes.push_back(finest);
  }
  if (sizes.empty()) return 0.0;
  const auto nth = sizes.begin() + static_cast<std::ptrdiff_t>(std::clamp(quantile, 0.0, 1.0) * (sizes.size() - 1));
  std::nth_element(sizes.begin(), nth, sizes.end());
  return *nth;
}

TriangleMesh decimate_mesh(const TriangleMesh& mesh, std::size_t max_faces, double max_error, DecimationStats* stats) {
  DecimationStats local;
  local.faces_before = mesh.faces.size();
  const bool over_budget = max_faces > 0 && mesh.faces.size() > max_faces;
  if (!over_budget && max_error <= 0.0) {
    local.faces_after = mesh.faces.size();
    if (stats) *stats = local;
    return mesh;
  }
  std::vector<std::uint32_t> indices;
  indices.reserve(3 * mesh.faces.size());
  for (const auto& f : mesh.faces) {
    for (int c = 0; c < 3; ++c) indices.push_back(static_cast<std::uint32_t>(f[c]));
  }
  std::vector<float> positions;
  positions.reserve(3 * mesh.vertices.size());
  for (const auto& v : mesh.vertices) positions.insert(positions.end(), {v.x(), v.y(), v.z()});
  // meshoptimizer's error is relative to the mesh extent.
  const float extent = meshopt_simplifyScale(positions.data(), mesh.vertices.size(), 3 * sizeof(float));
  const float target_error = extent > 0.0f ? static_cast<float>(max_error / extent) : 0.0f;
  // One simplifier pass over indices, in place.
  const auto simplify = [&](std::size_t target_indices, float error) {
    std::vector<std::uint32_t> simplified(indices.size());
    simplified.resize(meshopt_simplify(simplified.data(), indices.data(), indices.size(), positions.data(),
                                       mesh.vertices.size(), 3 * sizeof(float), target_indices, error, 0,
                                       &local.relative_error));
    indices = std::move(simplified);
  };
  if (max_error > 0.0) simplify(0, target_error);
  // The budget wins over the bound: a large error lets it decide.
  if (max_faces > 0 && indices.size() > 3 * max_faces) simplify(3 * max_faces, 1.0f);

  TriangleMesh out;
  std::vector<int> remap(mesh.vertices.size(), -1);
  for (std::size_t i = 0; i < indices.size(); i += 3) {
    Eigen::Vector3i face;
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t v = indices[i + c];
      if (remap[v] < 0) {
        remap[v] = static_cast<int>(out.vertices.size());
        out.vertices.push_back(mesh.vertices[v]);
        if (!mesh.normals.empty()) out.normals.push_back(mesh.normals[v]);
        if (!mesh.colors.empty()) out.colors.push_back(mesh.colors[v]);
      }
      face[c] = remap[v];
    }
    out.faces.push_back(face);
  }
  local.faces_after = out.faces.size();
  if (stats) *stats = local;
  return out;
}

namespace {

// The pages tiled into one image (a grid of equal cells, as square as the
// pages allow), scaled to fit max_size; every vertex's UV moved into its
// page's cell. A vertex belongs to one page (charts do not share vertices).
cv::Mat merge_pages(const TexturedMesh& mesh, int max_size, std::vector<Eigen::Vector2f>& uvs) {
  const int pages = static_cast<int>(mesh.atlases.size());
  int cell_w = 1, cell_h = 1;
  for (const cv::Mat& a : mesh.atlases) {
    cell_w = std::max(cell_w, a.cols);
    cell_h = std::max(cell_h, a.rows);
  }
  const int columns = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(pages)))));
  const int rows = std::max(1, (pages + columns - 1) / columns);
  cv::Mat grid(rows * cell_h, columns * cell_w, CV_8UC3, cv::Scalar(0, 0, 0));
  uvs = mesh.uvs;
  for (int p = 0; p < pages; ++p) {
    const cv::Mat& a = mesh.atlases[p];
    const int x0 = (p % columns) * cell_w, y0 = (p / columns) * cell_h;
    a.copyTo(grid(cv::Rect(x0, y0, a.cols, a.rows)));
    for (std::uint32_t v : mesh.indices[p]) {
      const Eigen::Vector2f& uv = mesh.uvs[v];
      uvs[v] = Eigen::Vector2f((x0 + uv.x() * a.cols) / grid.cols, (y0 + uv.y() * a.rows) / grid.rows);
    }
  }
  const double scale = std::min(1.0, static_cast<double>(max_size) / std::max(grid.cols, grid.rows));
  if (scale >= 1.0) return grid;
  cv::Mat small;
  const cv::Size size(std::max(1, static_cast<int>(std::floor(grid.cols * scale))),
                      std::max(1, static_cast<int>(std::floor(grid.rows * scale))));
  cv::resize(grid, small, size, 0, 0, cv::INTER_AREA);
  return small;  // UVs are relative: unchanged by the scaling
}

}  // namespace

TexturedMesh preview_model(const TexturedMesh& mesh,
                           std::size_t max_faces,
                           int max_atlas_size,
                           DecimationStats* stats) {
  DecimationStats local;
  TexturedMesh out;
  out.root_matrix = mesh.root_matrix;
  out.metric = mesh.metric;
  out.geo_origin = mesh.geo_origin;
  std::vector<Eigen::Vector2f> uvs;
  out.atlases.push_back(merge_pages(mesh, max_atlas_size, uvs));

  std::vector<std::uint32_t> indices;
  for (const auto& page : mesh.indices) indices.insert(indices.end(), page.begin(), page.end());
  local.faces_before = indices.size() / 3;
  if (local.faces_before > max_faces) {
    std::vector<float> positions;
    positions.reserve(3 * mesh.positions.size());
    for (const auto& v : mesh.positions) positions.insert(positions.end(), {v.x(), v.y(), v.z()});
    std::vector<std::uint32_t> simplified(indices.size());
    // A large target error lets the face budget decide.
    const std::size_t count =
        meshopt_simplify(simplified.data(), indices.data(), indices.size(), positions.data(), mesh.positions.size(),
                         3 * sizeof(float), 3 * max_faces, 1.0f, 0, &local.relative_error);
    if (count / 3 > max_faces) {
      // Locked borders (many small charts) can stop the simplifier short:
      // the sloppy simplifier reaches any budget.
      simplified.resize(indices.size());
      const std::size_t sloppy =
          meshopt_simplifySloppy(simplified.data(), indices.data(), indices.size(), positions.data(),
                                 mesh.positions.size(), 3 * sizeof(float), 3 * max_faces, 1.0f, &local.relative_error);
      simplified.resize(sloppy);
    } else {
      simplified.resize(count);
    }
    indices = std::move(simplified);
  }
  // Only the vertices still used, in first-use order.
  std::vector<std::int64_t> remap(mesh.positions.size(), -1);
  std::vector<std::uint32_t> page;
  page.reserve(indices.size());
  for (std::uint32_t v : indices) {
    if (remap[v] < 0) {
      remap[v] = static_cast<std::int64_t>(out.positions.size());
      out.positions.push_back(mesh.positions[v]);
      out.normals.push_back(mesh.normals[v]);
      out.uvs.push_back(uvs[v]);
    }
    page.push_back(static_cast<std::uint32_t>(remap[v]));
  }
  out.indices.push_back(std::move(page));
  local.faces_after = out.indices[0].size() / 3;
  if (stats) *stats = local;
  return out;
}

}  // namespace hos::texture
