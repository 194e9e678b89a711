#include "recon/recon_report.h"

#include "core/json_report.h"

namespace hos::recon {
namespace {

ReconReport report_from_json(const nlohmann::ordered_json& j) {
  ReconReport r;
  read_key(j, "vertices", r.vertices);
  read_key(j, "faces", r.faces);
  read_key(j, "grid", r.grid);
  read_key(j, "voxel_size", r.voxel_size);
  read_key(j, "resolution", r.resolution);
  read_key(j, "samples_per_occupied_cell", r.samples_per_occupied_cell);
  read_key(j, "samples", r.samples);
  read_key(j, "samples_dropped", r.samples_dropped);
  read_key(j, "multigrid_levels", r.multigrid_levels);
  read_key(j, "solver_iterations", r.solver_iterations);
  read_key(j, "relative_residual", r.relative_residual);
  read_key(j, "residual_history", r.residual_history);
  read_key(j, "solve_iterations", r.solve_iterations);
  read_key(j, "band_nodes", r.band_nodes);
  read_key(j, "isovalue", r.isovalue);
  read_key(j, "faces_before_trim", r.faces_before_trim);
  read_key(j, "faces_trimmed", r.faces_trimmed);
  read_key(j, "pieces", r.pieces);
  read_key(j, "debris_pieces_removed", r.debris_pieces_removed);
  read_key(j, "debris_faces_removed", r.debris_faces_removed);
  read_key(j, "debris_area_removed", r.debris_area_removed);
  read_key(j, "surface_area", r.surface_area);
  read_key(j, "seconds_field", r.seconds_field);
  read_key(j, "seconds_solve", r.seconds_solve);
  read_key(j, "seconds_mesh", r.seconds_mesh);
  read_key(j, "tiles", r.tiles);
  read_key(j, "largest_tile_nodes", r.largest_tile_nodes);
  read_key(j, "largest_join_nodes", r.largest_join_nodes);
  return r;
}

}  // namespace

ReconReport recon_report(const ReconResult& result) {
  const ReconStats& s = result.stats;
  ReconReport r;
  r.vertices = static_cast<std::int64_t>(result.mesh.num_vertices());
  r.faces = static_cast<std::int64_t>(result.mesh.num_faces());
  r.grid = {s.grid_dims.x(), s.grid_dims.y(), s.grid_dims.z()};
  r.voxel_size = s.voxel_size;
  r.resolution = s.resolution;
  r.samples_per_occupied_cell = s.samples_per_occupied_cell;
  r.samples = static_cast<std::int64_t>(s.num_samples);
  r.samples_dropped = static_cast<std::int64_t>(s.num_samples_dropped);
  r.multigrid_levels = s.multigrid_levels;
  r.solver_iterations = s.solver_iterations;
  r.relative_residual = s.relative_residual;
  r.residual_history = s.residual_history;
  r.solve_iterations = s.solve_iterations;
  r.band_nodes = s.band_nodes;
  r.isovalue = s.isovalue;
  r.faces_before_trim = static_cast<std::int64_t>(s.faces_before_trim);
  r.faces_trimmed = static_cast<std::int64_t>(s.faces_trimmed);
  r.pieces = static_cast<std::int64_t>(s.debris.components);
  r.debris_pieces_removed = static_cast<std::int64_t>(s.debris.components_removed);
  r.debris_faces_removed = static_cast<std::int64_t>(s.debris.faces_removed);
  r.debris_area_removed = s.debris.area_removed;
  r.surface_area = s.debris.area_kept;
  r.seconds_field = s.seconds_field;
  r.seconds_solve = s.seconds_solve;
  r.seconds_mesh = s.seconds_mesh;
  r.tiles = s.tiles;
  r.largest_tile_nodes = s.largest_tile_nodes;
  r.largest_join_nodes = s.largest_join_nodes;
  return r;
}

nlohmann::ordered_json to_json(const ReconReport& r) {
  nlohmann::ordered_json j;
  j["vertices"] = r.vertices;
  j["faces"] = r.faces;
  j["grid"] = r.grid;
  j["voxel_size"] = r.voxel_size;
  j["resolution"] = r.resolution;
  if (r.samples_per_occupied_cell > 0.0) j["samples_per_occupied_cell"] = r.samples_per_occupied_cell;
  j["samples"] = r.samples;
  j["samples_dropped"] = r.samples_dropped;
  j["multigrid_levels"] = r.multigrid_levels;
  j["solver_iterations"] = r.solver_iterations;
  j["relative_residual"] = r.relative_residual;
  j["residual_history"] = r.residual_history;
  j["solve_iterations"] = r.solve_iterations;
  j["band_nodes"] = r.band_nodes;
  j["isovalue"] = r.isovalue;
  j["faces_before_trim"] = r.faces_before_trim;
  j["faces_trimmed"] = r.faces_trimmed;
  j["pieces"] = r.pieces;
  j["debris_pieces_removed"] = r.debris_pieces_removed;
  j["debris_faces_removed"] = r.debris_faces_removed;
  j["debris_area_removed"] = r.debris_area_removed;
  j["surface_area"] = r.surface_area;
  j["seconds_field"] = r.seconds_field;
  j["seconds_solve"] = r.seconds_solve;
  j["seconds_mesh"] = r.seconds_mesh;
  if (r.tiles > 1) {
    j["tiles"] = r.tiles;
    j["largest_tile_nodes"] = r.largest_tile_nodes;
    j["largest_join_nodes"] = r.largest_join_nodes;
  }
  return j;
}

ReconReport read_recon_report(const std::filesystem::path& path) { return read_json_report(path, report_from_json); }

void write_recon_report(const std::filesystem::path& path, const ReconResult& result) {
  write_json_report(path, to_json(recon_report(result)));
}

}  // namespace hos::recon
