// Where a synthetic scene's surface is lost in each training view, by the
// angle at which the view sees it: every pixel where the true mesh is the
// nearest surface (rendered at the depth map's size) is one of
//   textureless   no depth: the window was too flat to be scored
//   unmatched     no depth: the best plane's cost was above mvs.max_cost
//   wrong         a depth farther than --tolerance from the true surface
//   right         a depth within it, and of those
//   fused         the ones a fused point (--points) lands on, within the
//                 tolerance of the true surface (in the pixel or its 8
//                 neighbours)
// as shares of the pixels of each incidence range (the angle between the
// true face's normal and the ray to the camera). Pixels near a silhouette
// (within --edge-radius pixels, the matching window's radius, of a pixel
// that sees no surface or a surface off this pixel's true plane by more
// than the tolerance) form a row of their own: there the window straddles
// two surfaces, and the objects' rims, seen at grazing angles by
// definition, would otherwise fill the grazing rows. Distances are to the
// plane of the true face the pixel sees; the tolerance is a fraction of the
// true mesh's bounding-box diagonal, as hos-eval's thresholds.
//
//   hos-mvs-depth-loss --model DIR --depth-maps DIR --truth gt_mesh.ply [--points points.ply]
//                      [--tolerance 0.005] [--edge-radius 4] [--map-view NAME --map FILE.ppm]
#include <CLI/CLI.hpp>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bench/mvs/depth_map_calibration.h"
#include "core/colmap_io.h"
#include "core/error.h"
#include "core/ply_io.h"
#include "mvs/depth_map_file.h"
#include "render/depth_buffer.h"

namespace {

constexpr std::array<double, 6> kIncidenceEdgesDeg = {0, 45, 60, 70, 80, 90};
constexpr int kBins = static_cast<int>(kIncidenceEdgesDeg.size()) - 1;
enum Outcome { kTexturelessPixel, kUnmatched, kWrong, kRight, kFused, kOutcomes };
constexpr std::array<const char*, kOutcomes> kOutcomeNames = {"textureless", "unmatched", "wrong", "right", "fused"};

int incidence_bin(double degrees) {
  for (int b = 0; b < kBins; ++b) {
    if (degrees < kIncidenceEdgesDeg[b + 1]) return b;
  }
  return kBins - 1;
}

// Rows: the incidence bins away from silhouettes, then the pixels near one;
// last column: the row's pixels.
constexpr int kNearSilhouette = kBins;
using Counts = std::array<std::array<long, kOutcomes + 1>, kBins + 1>;

// Adds the view's pixels of the true surface to counts and, when pixels is
// not null, writes each pixel's outcome there (kOutcomes where no true
// surface is seen).
void count_view(const hos::SparseModel& model,
                const hos::ImageRecord& image,
                const hos::mvs::DepthMap& map,
                const hos::TriangleMesh& truth,
                const hos::PointCloud* points,
                double tolerance,
                int edge_radius,
                Counts& counts,
                std::vector<Outcome>* pixels) {
  const Eigen::Matrix3d K = hos::bench::depth_map_calibration(model.camera_of(image), map);
  const int width = map.depth.cols, height = map.depth.rows;
  const Eigen::Matrix3d R = image.rotation(), K_inv = K.inverse();
  const Eigen::Vector3d t = image.cam_from_world_translation, centre = image.center();
  std::vector<Eigen::Vector3f> projected;
  projected.reserve(truth.vertices.size());
  for (const Eigen::Vector3f& v : truth.vertices) {
    const Eigen::Vector3d c = R * v.cast<double>() + t;
    const Eigen::Vector3d p = K * c;
    projected.emplace_back(static_cast<float>(p.x() / p.z()), static_cast<float>(p.y() / p.z()),
                           static_cast<float>(c.z()));
  }
  const hos::render::DepthBuffer buffer = hos::render::rasterize_depth(truth, projected, width, height);
  // The plane of the true face seen at pixel (px, py): a corner and the unit
  // normal; nullopt where no face is seen.
  const auto true_plane = [&](int px, int py) -> std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> {
    const int face = buffer.face_id.at<int>(py, px);
    if (face < 0) return std::nullopt;
    const Eigen::Vector3i& f = truth.faces[static_cast<std::size_t>(face)];
    const Eigen::Vector3d a = truth.vertices[f[0]].cast<double>();
    return std::pair{
        a, (truth.vertices[f[1]].cast<double>() - a).cross(truth.vertices[f[2]].cast<double>() - a).normalized()};
  };
  // The distance of x from that plane (what hos-eval measures, on a surface
  // flat at the tolerance's scale); infinite where no face is seen.
  const auto distance_to_truth = [&](int px, int py, const Eigen::Vector3d& x) {
    const auto plane = true_plane(px, py);
    return plane ? std::abs(plane->second.dot(x - plane->first)) : std::numeric_limits<double>::infinity();
  };
  // Pixels a fused point lands on within the tolerance (and their neighbours).
  std::vector<std::uint8_t> fused(map.depth.total(), 0);
  if (points) {
    for (const Eigen::Vector3f& p : points->positions) {
      const Eigen::Vector3d c = R * p.cast<double>() + t;
      if (c.z() <= 0) continue;
      const Eigen::Vector3d uv = K * c / c.z();
      const int x = static_cast<int>(std::floor(uv.x())), y = static_cast<int>(std::floor(uv.y()));
      if (x < 0 || y < 0 || x >= width || y >= height) continue;
      if (!(distance_to_truth(x, y, p.cast<double>()) <= tolerance)) continue;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          if (x + dx >= 0 && y + dy >= 0 && x + dx < width && y + dy < height) {
            fused[static_cast<std::size_t>(y + dy) * width + x + dx] = 1;
          }
        }
      }
    }
  }
  // The true surface's point at each pixel (NaN where none is seen).
  std::vector<Eigen::Vector3d> true_points(map.depth.total(), Eigen::Vector3d::Constant(std::nan("")));
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      if (buffer.face_id.at<int>(y, x) < 0) continue;
      const Eigen::Vector3d ray_cam = K_inv * Eigen::Vector3d(x + 0.5, y + 0.5, 1.0);
      true_points[static_cast<std::size_t>(y) * width + x] =
          R.transpose() * (ray_cam * static_cast<double>(buffer.depth.at<float>(y, x)) - t);
    }
  }
  const auto near_silhouette = [&](int x, int y, const Eigen::Vector3d& point, const Eigen::Vector3d& normal) {
    for (int ny = std::max(0, y - edge_radius); ny <= std::min(height - 1, y + edge_radius); ++ny) {
      for (int nx = std::max(0, x - edge_radius); nx <= std::min(width - 1, x + edge_radius); ++nx) {
        const Eigen::Vector3d& q = true_points[static_cast<std::size_t>(ny) * width + nx];
        if (!(std::abs(normal.dot(q - point)) <= tolerance)) return true;  // NaN: no surface
      }
    }
    return false;
  };
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const auto plane = true_plane(x, y);
      if (!plane) continue;
      const Eigen::Vector3d& normal = plane->second;
      const Eigen::Vector3d ray_cam = K_inv * Eigen::Vector3d(x + 0.5, y + 0.5, 1.0);
      const Eigen::Vector3d& point = true_points[static_cast<std::size_t>(y) * width + x];
      const double cos_incidence = std::abs(normal.dot((centre - point).normalized()));
      const int bin = near_silhouette(x, y, point, normal)
                          ? kNearSilhouette
                          : incidence_bin(std::acos(std::min(1.0, cos_incidence)) * 180.0 / M_PI);
      const std::size_t i = static_cast<std::size_t>(y) * width + x;
      ++counts[bin][kOutcomes];
      const float d = map.depth.at<float>(y, x);
      Outcome outcome = kFused;
      if (!(d > 0)) {
        outcome = map.cost.at<float>(y, x) == hos::mvs::kTexturelessCost ? kTexturelessPixel : kUnmatched;
      } else if (!(distance_to_truth(x, y, R.transpose() * (ray_cam * d - t)) <= tolerance)) {
        outcome = kWrong;
      } else {
        ++counts[bin][kRight];
        if (!fused[i]) outcome = kRight;
      }
      if (outcome != kRight) ++counts[bin][outcome];
      if (pixels) (*pixels)[i] = outcome;
    }
  }
}

// The view's outcomes as a PPM: blue textureless, red unmatched, magenta
// wrong, yellow right but not fused, white fused, black no true surface.
void write_map(const std::string& file, const std::vector<Outcome>& pixels, int width, int height) {
  constexpr std::array<std::array<std::uint8_t, 3>, kOutcomes + 1> kColours = {
      {{0, 0, 255}, {255, 0, 0}, {255, 0, 255}, {255, 255, 0}, {255, 255, 255}, {0, 0, 0}}};
  std::ofstream out(file, std::ios::binary);
  out << "P6 " << width << " " << height << " 255\n";
  for (Outcome o : pixels) out.write(reinterpret_cast<const char*>(kColours[o].data()), 3);
  if (!out) throw hos::OutputError(file, "the map");
}

void print_row(const std::string& label, const std::array<long, kOutcomes + 1>& row, long total) {
  const double n = static_cast<double>(std::max<long>(1, row[kOutcomes]));
  std::cout << "| " << label << " | " << row[kOutcomes] / static_cast<double>(std::max<long>(1, total)) << " |";
  for (int k = 0; k < kOutcomes; ++k) std::cout << ' ' << row[k] / n << " |";
  std::cout << "\n";
}

void print_table(const Counts& counts) {
  std::array<long, kOutcomes + 1> all{};
  for (const auto& row : counts) {
    for (int k = 0; k <= kOutcomes; ++k) all[k] += row[k];
  }
  std::cout << "| incidence (deg) | share of pixels |";
  for (const char* name : kOutcomeNames) std::cout << ' ' << name << " |";
  std::cout << "\n|---|---|";
  for (int k = 0; k < kOutcomes; ++k) std::cout << "---|";
  std::cout << "\n" << std::fixed << std::setprecision(3);
  for (int b = 0; b < kBins; ++b) {
    print_row(std::to_string(static_cast<int>(kIncidenceEdgesDeg[b])) + "-" +
                  std::to_string(static_cast<int>(kIncidenceEdgesDeg[b + 1])),
              counts[b], all[kOutcomes]);
  }
  print_row("near a silhouette", counts[kNearSilhouette], all[kOutcomes]);
  print_row("all", all, all[kOutcomes]);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"where a synthetic scene's surface is lost in each view, by incidence angle"};
  std::string model_dir, depth_maps, truth_file, points_file;
  double tolerance_fraction = 0.005;
  app.add_option("--model", model_dir, "the training views' sparse model (true cameras)")->required();
  app.add_option("--depth-maps", depth_maps, "folder of the views' .dmap files (hos-mvs --depth-maps)")->required();
  app.add_option("--truth", truth_file, "the true mesh (hos-synth's gt_mesh.ply)")->required();
  app.add_option("--points", points_file, "fused points (hos-mvs --output)");
  app.add_option("--tolerance", tolerance_fraction, "as a fraction of the true mesh's bounding-box diagonal");
  int edge_radius = 4;
  app.add_option("--edge-radius", edge_radius, "pixels near a silhouette: within this radius (mvs.window_radius)")
      ->check(CLI::Range(0, 32));
  std::string map_view, map_file;
  app.add_option("--map-view", map_view, "the view --map draws");
  app.add_option("--map", map_file, "a PPM of --map-view's pixels by outcome");
  CLI11_PARSE(app, argc, argv);
  try {
    const hos::SparseModel model = hos::read_colmap_model(model_dir);
    const hos::TriangleMesh truth = hos::read_mesh_ply(truth_file);
    Eigen::AlignedBox3f box;
    for (const Eigen::Vector3f& v : truth.vertices) box.extend(v);
    const double tolerance = tolerance_fraction * box.diagonal().norm();
    hos::PointCloud points;
    if (!points_file.empty()) points = hos::read_point_cloud_ply(points_file);
    Counts counts{};
    for (const auto& [id, image] : model.images) {
      const hos::mvs::DepthMap map = hos::mvs::read_depth_map_file(hos::mvs::depth_map_file(depth_maps, image.name));
      const bool drawn = !map_file.empty() && image.name == map_view;
      std::vector<Outcome> pixels(drawn ? map.depth.total() : 0, kOutcomes);
      count_view(model, image, map, truth, points_file.empty() ? nullptr : &points, tolerance, edge_radius, counts,
                 drawn ? &pixels : nullptr);
      if (drawn) write_map(map_file, pixels, map.depth.cols, map.depth.rows);
    }
    print_table(counts);
  } catch (const std::exception& e) {
    std::cerr << "hos-mvs-depth-loss: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
