// WS/recon/report.json: what hos-recon writes the pipeline reads back field
// by field, and a missing or damaged file is an InputError naming it.
#include "recon/recon_report.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "core/json_report.h"
#include "tests/support/damaged_file_checks.h"
#include "tests/support/test_support.h"

namespace hos::recon {
namespace {

// Every field away from its default, each value of its own.
ReconReport tiled_report() {
  ReconReport r;
  r.vertices = 1001;
  r.faces = 2002;
  r.grid = {65, 33, 17};
  r.voxel_size = 0.015625;
  r.resolution = 64;
  r.samples_per_occupied_cell = 7.5;
  r.samples = 40000;
  r.samples_dropped = 12;
  r.multigrid_levels = 4;
  r.solver_iterations = 31;
  r.relative_residual = 3.5e-7;
  r.residual_history = {0.5, 0.01, 1e-4, 0.2, 3.5e-7};
  r.solve_iterations = {3, 2};
  r.band_nodes = 123456;
  r.isovalue = -0.0625;
  r.faces_before_trim = 2100;
  r.faces_trimmed = 98;
  r.pieces = 3;
  r.debris_pieces_removed = 2;
  r.debris_faces_removed = 40;
  r.debris_area_removed = 0.005;
  r.surface_area = 0.85;
  r.seconds_field = 0.25;
  r.seconds_solve = 1.5;
  r.seconds_mesh = 0.75;
  r.tiles = 4;
  r.largest_tile_nodes = 70000;
  r.largest_join_nodes = 30000;
  return r;
}

void expect_equal(const ReconReport& r, const ReconReport& w) {
  EXPECT_EQ(r.vertices, w.vertices);
  EXPECT_EQ(r.faces, w.faces);
  EXPECT_EQ(r.grid, w.grid);
  EXPECT_EQ(r.voxel_size, w.voxel_size);
  EXPECT_EQ(r.resolution, w.resolution);
  EXPECT_EQ(r.samples_per_occupied_cell, w.samples_per_occupied_cell);
  EXPECT_EQ(r.samples, w.samples);
  EXPECT_EQ(r.samples_dropped, w.samples_dropped);
  EXPECT_EQ(r.multigrid_levels, w.multigrid_levels);
  EXPECT_EQ(r.solver_iterations, w.solver_iterations);
  EXPECT_EQ(r.relative_residual, w.relative_residual);
  EXPECT_EQ(r.residual_history, w.residual_history);
  EXPECT_EQ(r.solve_iterations, w.solve_iterations);
  EXPECT_EQ(r.band_nodes, w.band_nodes);
  EXPECT_EQ(r.isovalue, w.isovalue);
  EXPECT_EQ(r.faces_before_trim, w.faces_before_trim);
  EXPECT_EQ(r.faces_trimmed, w.faces_trimmed);
  EXPECT_EQ(r.pieces, w.pieces);
  EXPECT_EQ(r.debris_pieces_removed, w.debris_pieces_removed);
  EXPECT_EQ(r.debris_faces_removed, w.debris_faces_removed);
  EXPECT_EQ(r.debris_area_removed, w.debris_area_removed);
  EXPECT_EQ(r.surface_area, w.surface_area);
  EXPECT_EQ(r.seconds_field, w.seconds_field);
  EXPECT_EQ(r.seconds_solve, w.seconds_solve);
  EXPECT_EQ(r.seconds_mesh, w.seconds_mesh);
  EXPECT_EQ(r.tiles, w.tiles);
  EXPECT_EQ(r.largest_tile_nodes, w.largest_tile_nodes);
  EXPECT_EQ(r.largest_join_nodes, w.largest_join_nodes);
}

TEST(ReconReport, ReadsBackWhatItWrites) {
  hos::testing::TempDir dir;
  const ReconReport written = tiled_report();
  write_json_report(dir / "report.json", to_json(written));
  expect_equal(read_recon_report(dir / "report.json"), written);
}

// An untiled run whose grid was given leaves the tile keys and the density
// out of the file; reading gives their defaults back.
TEST(ReconReport, KeysLeftOutOfTheFileReadAsTheirDefaults) {
  hos::testing::TempDir dir;
  ReconReport written = tiled_report();
  written.samples_per_occupied_cell = 0.0;
  written.tiles = 1;
  written.largest_tile_nodes = 0;
  written.largest_join_nodes = 0;
  const nlohmann::ordered_json j = to_json(written);
  for (const char* key : {"samples_per_occupied_cell", "tiles", "largest_tile_nodes", "largest_join_nodes"}) {
    EXPECT_FALSE(j.contains(key)) << key;
  }
  write_json_report(dir / "report.json", j);
  expect_equal(read_recon_report(dir / "report.json"), written);
}

TEST(ReconReport, AMissingOrMalformedReportIsAnInputErrorNamingTheFile) {
  hos::testing::expect_input_error_naming_the_file(
      "report.json", [](const std::filesystem::path& file) { read_recon_report(file); },
      {"", "{\"faces\": 3", "null", R"({"residual_history": 0.5})", R"({"solve_iterations": ["a"]})",
       R"({"grid": {"x": 3}})", R"({"surface_area": "big"})"});
}

}  // namespace
}  // namespace hos::recon
