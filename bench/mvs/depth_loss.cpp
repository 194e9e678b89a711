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
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "apps/stage_main.h"
#include "bench/mvs/depth_map_calibration.h"
#include "core/colmap_io.h"
#include "core/error.h"
#include "core/option_set.h"
#include "core/ply_io.h"
#include "mvs/depth_map_file.h"
#include "mvs/mvs_options.h"
#include "mvs/view_selection.h"
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

// The true surface as one view's depth map sees it: per pixel the face
// (rendered at the map's size), its plane and the point on it.
class ViewTruth {
 public:
  ViewTruth(const hos::SparseModel& model,
            const hos::ImageRecord& image,
            const hos::mvs::DepthMap& map,
            const hos::TriangleMesh& truth)
      : truth_(truth),
        width_(map.depth.cols),
        height_(map.depth.rows),
        K_(hos::bench::depth_map_calibration(model.camera_of(image), map)),
        K_inv_(K_.inverse()),
        R_(image.rotation()),
        t_(image.cam_from_world_translation),
        centre_(image.center()) {
    std::vector<Eigen::Vector3f> projected;
    projected.reserve(truth.vertices.size());
    for (const Eigen::Vector3f& v : truth.vertices) {
      const Eigen::Vector3d c = R_ * v.cast<double>() + t_;
      const Eigen::Vector3d p = K_ * c;
      projected.emplace_back(static_cast<float>(p.x() / p.z()), static_cast<float>(p.y() / p.z()),
                             static_cast<float>(c.z()));
    }
    buffer_ = hos::render::rasterize_depth(truth, projected, width_, height_);
    points_.assign(static_cast<std::size_t>(width_) * height_, Eigen::Vector3d::Constant(std::nan("")));
    for (int y = 0; y < height_; ++y) {
      for (int x = 0; x < width_; ++x) {
        if (buffer_.face_id.at<int>(y, x) >= 0) points_[index(x, y)] = on_ray(x, y, buffer_.depth.at<float>(y, x));
      }
    }
  }

  int width() const { return width_; }
  int height() const { return height_; }
  std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * width_ + x; }

  // The world point at depth d on pixel (x, y)'s ray.
  Eigen::Vector3d on_ray(int x, int y, double d) const {
    return R_.transpose() * (K_inv_ * Eigen::Vector3d(x + 0.5, y + 0.5, 1.0) * d - t_);
  }

  // The unit normal of the true face seen at (x, y); nullopt where none is.
  std::optional<Eigen::Vector3d> normal(int x, int y) const {
    const int face = buffer_.face_id.at<int>(y, x);
    if (face < 0) return std::nullopt;
    const Eigen::Vector3i& f = truth_.faces[static_cast<std::size_t>(face)];
    const Eigen::Vector3d a = truth_.vertices[f[0]].cast<double>();
    return (truth_.vertices[f[1]].cast<double>() - a).cross(truth_.vertices[f[2]].cast<double>() - a).normalized();
  }

  // The distance of p from the plane of the true face seen at (x, y) (what
  // hos-eval measures, on a surface flat at the tolerance's scale); NaN
  // where no face is seen.
  double distance(int x, int y, const Eigen::Vector3d& p) const {
    const auto n = normal(x, y);
    return n ? std::abs(n->dot(p - points_[index(x, y)])) : std::nan("");
  }

  // The angle (degrees) between the true face's normal at (x, y) and the
  // ray to the camera.
  double incidence_deg(int x, int y, const Eigen::Vector3d& normal) const {
    const double c = std::abs(normal.dot((centre_ - points_[index(x, y)]).normalized()));
    return std::acos(std::min(1.0, c)) * 180.0 / M_PI;
  }

  // True where a pixel within radius sees no surface, or a point off the
  // plane of the face seen at (x, y) by more than tolerance.
  bool near_silhouette(int x, int y, const Eigen::Vector3d& normal, int radius, double tolerance) const {
    const Eigen::Vector3d& p = points_[index(x, y)];
    for (int ny = std::max(0, y - radius); ny <= std::min(height_ - 1, y + radius); ++ny) {
      for (int nx = std::max(0, x - radius); nx <= std::min(width_ - 1, x + radius); ++nx) {
        if (!(std::abs(normal.dot(points_[index(nx, ny)] - p)) <= tolerance)) return true;  // NaN: none
      }
    }
    return false;
  }

  // Whether this view sees p: it projects into the frame onto the true face
  // whose plane lies within tolerance of it (not behind another surface).
  bool sees(const Eigen::Vector3d& p, double tolerance) const {
    const Eigen::Vector3d c = R_ * p + t_;
    if (c.z() <= 0) return false;
    const Eigen::Vector3d uv = K_ * c / c.z();
    const int x = static_cast<int>(std::floor(uv.x())), y = static_cast<int>(std::floor(uv.y()));
    return x >= 0 && y >= 0 && x < width_ && y < height_ && distance(x, y, p) <= tolerance;
  }

  // The true point at (x, y) (NaN where no face is seen).
  const Eigen::Vector3d& point(int x, int y) const { return points_[index(x, y)]; }

  // Pixels a fused point lands on within the tolerance of the truth, and
  // their 8 neighbours.
  std::vector<std::uint8_t> fused_pixels(const hos::PointCloud& cloud, double tolerance) const {
    std::vector<std::uint8_t> fused(points_.size(), 0);
    for (const Eigen::Vector3f& p : cloud.positions) {
      const Eigen::Vector3d c = R_ * p.cast<double>() + t_;
      if (c.z() <= 0) continue;
      const Eigen::Vector3d uv = K_ * c / c.z();
      const int x = static_cast<int>(std::floor(uv.x())), y = static_cast<int>(std::floor(uv.y()));
      if (x < 0 || y < 0 || x >= width_ || y >= height_ || !(distance(x, y, p.cast<double>()) <= tolerance)) {
        continue;
      }
      for (int ny = std::max(0, y - 1); ny <= std::min(height_ - 1, y + 1); ++ny) {
        for (int nx = std::max(0, x - 1); nx <= std::min(width_ - 1, x + 1); ++nx) fused[index(nx, ny)] = 1;
      }
    }
    return fused;
  }

 private:
  const hos::TriangleMesh& truth_;
  int width_, height_;
  Eigen::Matrix3d K_, K_inv_, R_;
  Eigen::Vector3d t_, centre_;
  hos::render::DepthBuffer buffer_;
  std::vector<Eigen::Vector3d> points_;  // NaN where no face is seen
};

// Pixels away from silhouettes by how many of the view's sources see their
// true point: 0, 1, 2, 3 or more (rows); columns as Counts'.
constexpr int kSourceRows = 4;
using SourceCounts = std::array<std::array<long, kOutcomes + 1>, kSourceRows>;

// Adds the view's pixels of the true surface to counts (and those away from
// silhouettes to by_sources, by how many of sources see them) and, when
// pixels is not null, writes each pixel's outcome there (kOutcomes where no
// true surface is seen).
void count_view(const ViewTruth& view,
                const std::vector<const ViewTruth*>& sources,
                const hos::mvs::DepthMap& map,
                const hos::PointCloud* points,
                double tolerance,
                int edge_radius,
                Counts& counts,
                SourceCounts& by_sources,
                std::vector<Outcome>* pixels) {
  const std::vector<std::uint8_t> fused = view.fused_pixels(points ? *points : hos::PointCloud{}, tolerance);
  for (int y = 0; y < view.height(); ++y) {
    for (int x = 0; x < view.width(); ++x) {
      const auto normal = view.normal(x, y);
      if (!normal) continue;
      const int bin = view.near_silhouette(x, y, *normal, edge_radius, tolerance)
                          ? kNearSilhouette
                          : incidence_bin(view.incidence_deg(x, y, *normal));
      ++counts[bin][kOutcomes];
      const float d = map.depth.at<float>(y, x);
      Outcome outcome = kFused;
      if (!(d > 0)) {
        outcome = map.cost.at<float>(y, x) == hos::mvs::kTexturelessCost ? kTexturelessPixel : kUnmatched;
      } else if (!(view.distance(x, y, view.on_ray(x, y, d)) <= tolerance)) {
        outcome = kWrong;
      } else {
        ++counts[bin][kRight];
        if (!points || !fused[view.index(x, y)]) outcome = kRight;
      }
      if (outcome != kRight) ++counts[bin][outcome];
      if (pixels) (*pixels)[view.index(x, y)] = outcome;
      if (bin == kNearSilhouette) continue;
      int seeing = 0;
      for (const ViewTruth* source : sources) seeing += source->sees(view.point(x, y), tolerance) ? 1 : 0;
      auto& row = by_sources[std::min(seeing, kSourceRows - 1)];
      ++row[kOutcomes];
      if (outcome == kFused) ++row[kRight];
      ++row[outcome];
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

void print_header(const std::string& rows) {
  std::cout << "| " << rows << " | share of pixels |";
  for (const char* name : kOutcomeNames) std::cout << ' ' << name << " |";
  std::cout << "\n|---|---|";
  for (int k = 0; k < kOutcomes; ++k) std::cout << "---|";
  std::cout << "\n" << std::fixed << std::setprecision(3);
}

void print_table(const Counts& counts) {
  std::array<long, kOutcomes + 1> all{};
  for (const auto& row : counts) {
    for (int k = 0; k <= kOutcomes; ++k) all[k] += row[k];
  }
  print_header("incidence (deg)");
  for (int b = 0; b < kBins; ++b) {
    print_row(std::to_string(static_cast<int>(kIncidenceEdgesDeg[b])) + "-" +
                  std::to_string(static_cast<int>(kIncidenceEdgesDeg[b + 1])),
              counts[b], all[kOutcomes]);
  }
  print_row("near a silhouette", counts[kNearSilhouette], all[kOutcomes]);
  print_row("all", all, all[kOutcomes]);
}

void print_source_table(const SourceCounts& counts) {
  long total = 0;
  for (const auto& row : counts) total += row[kOutcomes];
  std::cout << "\n";
  print_header("sources that see the point");
  for (int r = 0; r < kSourceRows; ++r) {
    print_row(std::to_string(r) + (r + 1 == kSourceRows ? " or more" : ""), counts[r], total);
  }
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
  hos::apps::CommonStageFlags mvs_flags;
  app.add_option("--set", mvs_flags.assignments, "mvs.key=value as hos-mvs took it (the source views)");
  CLI11_PARSE(app, argc, argv);
  try {
    // The source views hos-mvs chose, from the same mvs options.
    hos::mvs::MvsOptions mvs_options;
    hos::OptionSet mvs_set("mvs");
    hos::mvs::register_options(mvs_set, mvs_options);
    hos::apps::apply_config_and_overrides(mvs_set, mvs_flags);
    const hos::SparseModel model = hos::read_colmap_model(model_dir);
    const hos::TriangleMesh truth = hos::read_mesh_ply(truth_file);
    Eigen::AlignedBox3f box;
    for (const Eigen::Vector3f& v : truth.vertices) box.extend(v);
    const double tolerance = tolerance_fraction * box.diagonal().norm();
    hos::PointCloud points;
    if (!points_file.empty()) points = hos::read_point_cloud_ply(points_file);
    // Every view's maps and true surface first: each view's sources need
    // theirs.
    std::map<int, hos::mvs::DepthMap> maps;
    std::map<int, ViewTruth> views;
    for (const auto& [id, image] : model.images) {
      maps[id] = hos::mvs::read_depth_map_file(hos::mvs::depth_map_file(depth_maps, image.name));
      views.try_emplace(id, model, image, maps[id], truth);
    }
    const std::vector<std::vector<int>> sources = hos::mvs::select_source_views(model, mvs_options);
    Counts counts{};
    SourceCounts by_sources{};
    std::size_t v = 0;
    for (const auto& [id, image] : model.images) {
      std::vector<const ViewTruth*> source_views;
      for (int s : sources[v++]) source_views.push_back(&views.at(s));
      const bool drawn = !map_file.empty() && image.name == map_view;
      std::vector<Outcome> pixels(drawn ? maps[id].depth.total() : 0, kOutcomes);
      count_view(views.at(id), source_views, maps[id], points_file.empty() ? nullptr : &points, tolerance, edge_radius,
                 counts, by_sources, drawn ? &pixels : nullptr);
      if (drawn) write_map(map_file, pixels, maps[id].depth.cols, maps[id].depth.rows);
    }
    print_table(counts);
    print_source_table(by_sources);
  } catch (const std::exception& e) {
    std::cerr << "hos-mvs-depth-loss: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
