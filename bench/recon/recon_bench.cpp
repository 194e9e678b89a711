// hos-recon-bench: inputs and measurements for bench/recon/*.sh (not a test).
//   hos-recon-bench points --shape sphere|sphere6|primitives --count N [--noise S] --output X.ply
//   hos-recon-bench sphere-error --mesh M.ply [--radius R]
//   hos-recon-bench scans --conf bun.conf --output X.ply   (oriented scan points with colours)
//   hos-recon-bench isosurface --field sphere|gyroid [--size 256] [--repeat 3]
//     (extraction time, best of the repeats, triangles, smallest angles, topology)
// Points are written with red/green/blue so COLMAP's poisson_mesher accepts them.
#include <CLI/CLI.hpp>
#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <iostream>

#include "core/ply_io.h"
#include "eval/mesh_sanity.h"
#include "recon/isosurface.h"
#include "recon/scans.h"
#include "synth/shapes.h"

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

// An analytic field on a size^3 grid of unit spacing centred on the origin:
// a sphere's signed distance (radius 0.39 size) or a gyroid-like triply
// periodic surface (period 40 nodes), much more surface per cell.
hos::recon::ScalarGrid analytic_field(const std::string& field, int size) {
  hos::recon::GridGeometry g;
  g.dims = Eigen::Vector3i::Constant(size);
  g.origin = Eigen::Vector3d::Constant(-0.5 * (size - 1));
  hos::recon::ScalarGrid f(g);
  const double radius = 0.39 * size + 0.3, s = 2.0 * M_PI / 40.0;
#pragma omp parallel for schedule(static)
  for (int k = 0; k < size; ++k) {
    for (int j = 0; j < size; ++j) {
      for (int i = 0; i < size; ++i) {
        const Eigen::Vector3d p = g.position(i, j, k);
        f.values[g.index(i, j, k)] = field == "sphere" ? p.norm() - radius
                                                       : std::sin(s * p.x()) * std::cos(s * p.y()) +
                                                             std::sin(s * p.y()) * std::cos(s * p.z()) +
                                                             std::sin(s * p.z()) * std::cos(s * p.x()) - 0.3;
      }
    }
  }
  return f;
}

void report_isosurface(const std::string& field, int size, int repeat) {
  const hos::recon::ScalarGrid f = analytic_field(field, size);
  hos::TriangleMesh mesh;
  double best = 1e30;
  for (int r = 0; r < std::max(repeat, 1); ++r) {
    const auto start = std::chrono::steady_clock::now();
    mesh = hos::recon::extract_isosurface(f, 0.0);
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  double min_angle = 180.0;
  std::size_t below10 = 0, below5 = 0;
  for (const auto& face : mesh.faces) {
    double smallest = 180.0;
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d u = (mesh.vertices[face[(c + 1) % 3]] - mesh.vertices[face[c]]).cast<double>();
      const Eigen::Vector3d v = (mesh.vertices[face[(c + 2) % 3]] - mesh.vertices[face[c]]).cast<double>();
      smallest = std::min(smallest, std::atan2(u.cross(v).norm(), u.dot(v)) * 180.0 / M_PI);
    }
    min_angle = std::min(min_angle, smallest);
    below10 += smallest < 10.0;
    below5 += smallest < 5.0;
  }
  const hos::eval::MeshSanity topology = hos::eval::check_mesh_sanity(mesh);
  const double n = std::max<double>(mesh.num_faces(), 1.0);
  std::cout << field << " " << size << "^3: seconds " << best << " vertices " << mesh.num_vertices() << " triangles "
            << mesh.num_faces() << " min_angle_deg " << min_angle << " below_10deg_pct " << 100.0 * below10 / n
            << " below_5deg_pct " << 100.0 * below5 / n << " watertight " << topology.watertight << " misoriented "
            << topology.inconsistent_edges << " euler " << topology.euler_characteristic << "\n";
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
  std::string field = "sphere";
  int size = 256, repeat = 3;
  auto* iso = app.add_subcommand("isosurface", "time and measure the isosurface of an analytic field");
  iso->add_option("--field", field, "sphere | gyroid");
  iso->add_option("--size", size, "grid nodes per axis");
  iso->add_option("--repeat", repeat, "extractions to time (the best is reported)");
  CLI11_PARSE(app, argc, argv);
  namespace t = hos::synth;
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
      std::cout << "rms " << std::sqrt(sum2 / mesh.num_vertices()) << " max " << max << " faces " << mesh.num_faces()
                << "\n";
    } else if (iso->parsed()) {
      report_isosurface(field, size, repeat);
    } else if (scans->parsed()) {
      hos::write_point_cloud_ply(output, with_colors(hos::recon::load_stanford_scans(conf, hos::null_reporter())));
    }
  } catch (const std::exception& e) {
    std::cerr << "hos-recon-bench: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
