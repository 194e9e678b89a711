// The recon stage's report (hos-recon --report FILE, WS/recon/report.json in
// a pipeline run) for the run report: grid, samples, the solver's residual
// per iteration, isovalue, trimming, debris and times. Its JSON keys are in
// recon_report.cpp alone: the stage writes and the pipeline reads it through
// these functions.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <vector>

#include "recon/reconstruct.h"

namespace hos::recon {

struct ReconReport {
  std::int64_t vertices = 0;
  std::int64_t faces = 0;
  std::array<int, 3> grid{};  // nodes along x, y, z
  double voxel_size = 0.0;
  int resolution = 0;
  double samples_per_occupied_cell = 0.0;  // 0: not chosen from the density (left out of the file)
  std::int64_t samples = 0;
  std::int64_t samples_dropped = 0;
  int multigrid_levels = 0;
  int solver_iterations = 0;
  double relative_residual = 0.0;
  std::vector<double> residual_history;  // every solve's iterations in turn
  std::vector<int> solve_iterations;     // iterations of each solve
  std::int64_t band_nodes = 0;
  double isovalue = 0.0;
  std::int64_t faces_before_trim = 0;
  std::int64_t faces_trimmed = 0;
  std::int64_t pieces = 0;  // connected pieces before the debris removal
  std::int64_t debris_pieces_removed = 0;
  std::int64_t debris_faces_removed = 0;
  double debris_area_removed = 0.0;
  double surface_area = 0.0;  // kept
  double seconds_field = 0.0;
  double seconds_solve = 0.0;
  double seconds_mesh = 0.0;
  // Tiled runs only (tiles > 1; the tile keys are left out of the file otherwise).
  int tiles = 1;
  std::int64_t largest_tile_nodes = 0;
  std::int64_t largest_join_nodes = 0;
};

// The report of a run.
ReconReport recon_report(const ReconResult& result);

nlohmann::ordered_json to_json(const ReconReport& report);
// Throws InputError naming the file when it is missing or malformed.
ReconReport read_recon_report(const std::filesystem::path& path);

// Writes recon_report(result) atomically; throws OutputError.
void write_recon_report(const std::filesystem::path& path, const ReconResult& result);

}  // namespace hos::recon
