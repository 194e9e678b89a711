// hos-recon-bench: inputs and measurements for bench/recon/*.sh (not a test).
//   hos-recon-bench points --shape sphere|sphere6|primitives --count N [--noise S] --output X.ply
//   hos-recon-bench sphere-error --mesh M.ply [--radius R]
//   hos-recon-bench scans --conf bun.conf --output X.ply   (oriented scan points with colours)
// Points are written with red/green/blue so COLMAP's poisson_mesher accepts them.
#include <CLI/CLI.hpp>
#include <cmath>
#include <iostream>

#include "core/ply_io.h"
#include "recon/scans.h"
#include "tests/recon/shape_samples.h"

namespace {

hos::PointCloud with_colors(hos::PointCloud cloud) {
  cloud.colors.assign(cloud.size(), hos::Rgb8{128, 128, 128});
  return cloud;
}

void append(hos::PointCloud& into, const hos::PointCloud& part, const Eigen::Vector3f& shift) {
  for (std::size_t i = 0; i < part.size(); ++i) {
    into.positions.push_back(part.positions[i] + shift);
    into.normals.push_back(part.normals[i]);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hos-recon-bench: benchmark inputs and measurements"};
  app.require_subcommand(1);
  std::string shape = "sphere", output, mesh_path, conf;
  int count = 240000;
  double noise = 0.002, radius = 1.0;
  auto* points = app.add_subcommand("points", "sample an analytic shape");
  points->add_option("--shape", shape, "sphere | sphere6 | primitives");
  points->add_option("--count", count, "number of points");
  points->add_option("--noise", noise, "noise along the normal");
  points->add_option("--output", output)->required();
  auto* error = app.add_subcommand("sphere-error", "distance of mesh vertices to the sphere");
  error->add_option("--mesh", mesh_path)->required();
  error->add_option("--radius", radius);
  auto* scans = app.add_subcommand("scans", "oriented points of a Stanford .conf");
  scans->add_option("--conf", conf)->required();
  scans->add_option("--output", output)->required();
  CLI11_PARSE(app, argc, argv);
  namespace t = hos::recon::testing;
  try {
    if (points->parsed()) {
      hos::PointCloud cloud;
      if (shape == "sphere" || shape == "sphere6") {
        cloud = t::sample_sphere(count, 1.0, noise, 1);
        if (shape == "sphere6") t::coarsen_to_axis_directions(cloud);
      } else if (shape == "primitives") {
        // A set of primitives in the spirit of the paper's Fig. 1.
        append(cloud, t::sample_sphere(count / 4, 0.6, noise, 1), Eigen::Vector3f(-1.0f, 0, 0));
        append(cloud, t::sample_torus(count / 4, 0.7, 0.25, noise, 2), Eigen::Vector3f(1.0f, 0, 0));
        append(cloud, t::sample_rounded_box(count / 2, 0.6, 0.15, noise, 3), Eigen::Vector3f(0, 1.6f, 0));
      } else {
        std::cerr << "unknown shape " << shape << "\n";
        return 2;
      }
      hos::write_point_cloud_ply(output, with_colors(cloud));
    } else if (error->parsed()) {
      const hos::TriangleMesh mesh = hos::read_mesh_ply(mesh_path);
      double sum2 = 0.0, max = 0.0;
      for (const auto& v : mesh.vertices) {
        const double d = std::abs(v.cast<double>().norm() - radius);
        sum2 += d * d;
        max = std::max(max, d);
      }
      std::cout << "rms " << std::sqrt(sum2 / mesh.num_vertices()) << " max " << max << " faces "
                << mesh.num_faces() << "\n";
    } else if (scans->parsed()) {
      hos::write_point_cloud_ply(output,
                                 with_colors(hos::recon::load_stanford_scans(conf, hos::null_reporter())));
    }
  } catch (const std::exception& e) {
    std::cerr << "hos-recon-bench: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
