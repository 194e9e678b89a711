// Where a held-out photo's surface is lost, stage by stage, on real photos
// without a true surface: the share of the held-out photo's pixels that each
// stage's output covers when projected through the held-out camera (in the
// training model's frame, as with an SfM shared between the held-out photo
// and the training photos). Coverage is counted on a grid of cells of
// --cell x --cell photo pixels, fine enough for a surface of photo
// resolution to fill every cell it covers:
//   depth maps   every depth pixel of every training view (hos-mvs --depth-maps),
//                and the cells that the depths of two views or more reach
//   points       a point cloud (--points LABEL=FILE)
//   meshes       a mesh, rasterised (--mesh LABEL=FILE)
// A cell counts as covered when anything lands in it, in front or behind (no
// occlusion test), so the figures are upper bounds of what a render covers.
// Rows: every cell, and the photo's lower third (where the ground of photos
// taken standing is).
//
// --map writes a PPM of the cells: white where the last stage covers the
// cell, else the colour of the first stage that does not (black, red,
// magenta, blue, green, yellow, cyan in stage order).
//
//   hos-mvs-holdout-loss --view-model DIR --view NAME --model DIR [--depth-maps DIR]
//                        [--stage LABEL=FILE]... [--cell 8] [--map FILE.ppm]
#include <CLI/CLI.hpp>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

#include "bench/mvs/depth_map_calibration.h"
#include "core/colmap_io.h"
#include "core/error.h"
#include "core/ply_io.h"
#include "mvs/depth_map_file.h"

namespace {

// Cells of the held-out photo, marked when some surface lands in them.
struct CoverageGrid {
  Eigen::Matrix3d K;  // of the grid (cell units)
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  int cols = 0, rows = 0;
  std::vector<std::uint8_t> covered;

  void mark(const Eigen::Vector3d& world) {
    const Eigen::Vector3d c = R * world + t;
    if (c.z() <= 0) return;
    const Eigen::Vector3d uv = K * c / c.z();
    const int x = static_cast<int>(std::floor(uv.x())), y = static_cast<int>(std::floor(uv.y()));
    if (x >= 0 && y >= 0 && x < cols && y < rows) covered[static_cast<std::size_t>(y) * cols + x] = 1;
  }

  // Cells whose centre lies inside the projected triangle, and the cells of
  // its corners (a triangle smaller than a cell).
  void mark_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    Eigen::Vector2d p[3];
    const Eigen::Vector3d w[3] = {a, b, c};
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d q = R * w[i] + t;
      if (q.z() <= 0) return;
      p[i] = (K * q / q.z()).head<2>();
      mark(w[i]);
    }
    const double area = (p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[1] - p[0]).y() * (p[2] - p[0]).x();
    if (std::abs(area) < 1e-12) return;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({p[0].x(), p[1].x(), p[2].x()}))));
    const int x1 = std::min(cols - 1, static_cast<int>(std::ceil(std::max({p[0].x(), p[1].x(), p[2].x()}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({p[0].y(), p[1].y(), p[2].y()}))));
    const int y1 = std::min(rows - 1, static_cast<int>(std::ceil(std::max({p[0].y(), p[1].y(), p[2].y()}))));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d s(x + 0.5, y + 0.5);
        bool inside = true;
        for (int i = 0; i < 3 && inside; ++i) {
          const Eigen::Vector2d e = p[(i + 1) % 3] - p[i], f = s - p[i];
          inside = (e.x() * f.y() - e.y() * f.x()) * area >= 0;
        }
        if (inside) covered[static_cast<std::size_t>(y) * cols + x] = 1;
      }
    }
  }

  // Covered share of the rows [first_row, rows).
  double share(int first_row) const {
    std::size_t n = 0;
    for (std::size_t i = static_cast<std::size_t>(first_row) * cols; i < covered.size(); ++i) n += covered[i];
    return static_cast<double>(n) / (static_cast<double>(rows - first_row) * cols);
  }
};

CoverageGrid make_grid(const hos::SparseModel& model, const std::string& name, int cell) {
  const hos::ImageRecord* image = model.find_image(name);
  if (!image) throw hos::InputError(name, "not an image of the held-out view's model");
  const hos::Camera& camera = model.camera_of(*image);
  CoverageGrid g;
  g.cols = (camera.width + cell - 1) / cell;
  g.rows = (camera.height + cell - 1) / cell;
  g.K = camera.calibration_matrix();
  g.K.topRows<2>() /= cell;
  g.R = image->rotation();
  g.t = image->cam_from_world_translation;
  g.covered.assign(static_cast<std::size_t>(g.cols) * g.rows, 0);
  return g;
}

// Every depth pixel of every view of the model with a .dmap in folder, into
// grid; into two_views only the cells the depths of two views or more reach.
void mark_depth_maps(CoverageGrid& grid,
                     CoverageGrid& two_views,
                     const hos::SparseModel& model,
                     const std::string& folder) {
  std::vector<int> views(grid.covered.size(), 0);
  for (const auto& [id, image] : model.images) {
    std::fill(grid.covered.begin(), grid.covered.end(), std::uint8_t{0});
    const std::filesystem::path file = hos::mvs::depth_map_file(folder, image.name);
    if (!std::filesystem::exists(file)) continue;
    const hos::mvs::DepthMap map = hos::mvs::read_depth_map_file(file);
    const Eigen::Matrix3d K = hos::bench::depth_map_calibration(model.camera_of(image), map);
    const Eigen::Matrix3d K_inv = K.inverse(), Rt = image.rotation().transpose();
    for (int y = 0; y < map.depth.rows; ++y) {
      for (int x = 0; x < map.depth.cols; ++x) {
        const float d = map.depth.at<float>(y, x);
        if (!(d > 0)) continue;
        const Eigen::Vector3d c = K_inv * Eigen::Vector3d(x + 0.5, y + 0.5, 1.0) * d;
        grid.mark(Rt * (c - image.cam_from_world_translation));
      }
    }
    for (std::size_t i = 0; i < views.size(); ++i) views[i] += grid.covered[i];
  }
  for (std::size_t i = 0; i < views.size(); ++i) {
    grid.covered[i] = views[i] >= 1;
    two_views.covered[i] = views[i] >= 2;
  }
}

std::pair<std::string, std::string> split_label(const std::string& s) {
  const auto eq = s.find('=');
  if (eq == std::string::npos) throw hos::ConfigError(s, "expected LABEL=FILE");
  return {s.substr(0, eq), s.substr(eq + 1)};
}

// The map --map writes (see the top of the file).
void write_loss_map(const std::string& file, const std::vector<std::pair<std::string, CoverageGrid>>& rows) {
  static const unsigned char colours[][3] = {{0, 0, 0},   {255, 0, 0},   {255, 0, 255}, {0, 0, 255},
                                             {0, 160, 0}, {255, 255, 0}, {0, 255, 255}};
  const CoverageGrid& g = rows.front().second;
  std::ofstream out(file, std::ios::binary);
  out << "P6\n" << g.cols << " " << g.rows << "\n255\n";
  for (std::size_t i = 0; i < g.covered.size(); ++i) {
    unsigned char rgb[3] = {255, 255, 255};
    if (!rows.back().second.covered[i]) {
      std::size_t k = 0;
      while (k + 1 < rows.size() && rows[k].second.covered[i]) ++k;
      std::copy_n(colours[std::min<std::size_t>(k, 6)], 3, rgb);
    }
    out.write(reinterpret_cast<const char*>(rgb), 3);
  }
  if (!out) throw hos::OutputError(file, "the map");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"share of a held-out photo's pixels each stage's output covers"};
  std::string view_model, view, model_dir, depth_maps;
  std::vector<std::string> stages;
  int cell = 8;
  std::string map_file;
  app.add_option("--view-model", view_model, "sparse model holding the held-out view (training frame)")->required();
  app.add_option("--view", view, "the held-out image's name")->required();
  app.add_option("--model", model_dir, "the training views' sparse model (depth maps' cameras)")->required();
  app.add_option("--depth-maps", depth_maps, "folder of the training views' .dmap files");
  app.add_option("--stage", stages, "LABEL=FILE: a points or mesh PLY (faces: rasterised), in order");
  app.add_option("--cell", cell, "grid cell size in photo pixels")->check(CLI::Range(1, 64));
  app.add_option("--map", map_file, "write a PPM of where each cell is lost");
  CLI11_PARSE(app, argc, argv);
  try {
    const hos::SparseModel held = hos::read_colmap_model(view_model);
    const hos::SparseModel training = hos::read_colmap_model(model_dir);
    std::vector<std::pair<std::string, CoverageGrid>> rows;
    if (!depth_maps.empty()) {
      CoverageGrid g = make_grid(held, view, cell), two = make_grid(held, view, cell);
      mark_depth_maps(g, two, training, depth_maps);
      rows.emplace_back("depth maps, every pixel", std::move(g));
      rows.emplace_back("depth maps of two views or more", std::move(two));
    }
    for (const std::string& s : stages) {
      const auto [label, file] = split_label(s);
      CoverageGrid g = make_grid(held, view, cell);
      const hos::TriangleMesh mesh = hos::read_mesh_ply(file);
      for (const auto& v : mesh.vertices) g.mark(v.cast<double>());
      for (const auto& f : mesh.faces) {
        g.mark_triangle(mesh.vertices[f[0]].cast<double>(), mesh.vertices[f[1]].cast<double>(),
                        mesh.vertices[f[2]].cast<double>());
      }
      rows.emplace_back(label, std::move(g));
    }
    std::cout << "| stage output | covered, whole photo | lost there | covered, lower third | lost there |\n"
                 "|---|---|---|---|---|\n"
              << std::fixed << std::setprecision(3);
    double previous_all = 1.0, previous_low = 1.0;
    for (const auto& [label, g] : rows) {
      const double all = g.share(0), low = g.share(g.rows * 2 / 3);
      std::cout << "| " << label << " | " << all << " | " << previous_all - all << " | " << low << " | "
                << previous_low - low << " |\n";
      previous_all = all;
      previous_low = low;
    }
    if (!map_file.empty()) write_loss_map(map_file, rows);
  } catch (const std::exception& e) {
    std::cerr << "hos-mvs-holdout-loss: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
