#include "recon/recon_report.h"

#include "core/json_report.h"

namespace hos::recon {

nlohmann::ordered_json recon_report_json(const ReconResult& result) {
  const ReconStats& s = result.stats;
  nlohmann::ordered_json j;
  j["vertices"] = result.mesh.num_vertices();
  j["faces"] = result.mesh.num_faces();
  j["grid"] = {s.grid_dims.x(), s.grid_dims.y(), s.grid_dims.z()};
  j["voxel_size"] = s.voxel_size;
  j["resolution"] = s.resolution;
  if (s.samples_per_occupied_cell > 0.0) j["samples_per_occupied_cell"] = s.samples_per_occupied_cell;
  j["samples"] = s.num_samples;
  j["samples_dropped"] = s.num_samples_dropped;
  j["multigrid_levels"] = s.multigrid_levels;
  j["solver_iterations"] = s.solver_iterations;
  j["relative_residual"] = s.relative_residual;
  j["residual_history"] = s.residual_history;
  j["solve_iterations"] = s.solve_iterations;
  j["band_nodes"] = s.band_nodes;
  j["isovalue"] = s.isovalue;
  j["faces_before_trim"] = s.faces_before_trim;
  j["faces_trimmed"] = s.faces_trimmed;
  j["pieces"] = s.debris.components;
  j["debris_pieces_removed"] = s.debris.components_removed;
  j["debris_faces_removed"] = s.debris.faces_removed;
  j["debris_area_removed"] = s.debris.area_removed;
  j["surface_area"] = s.debris.area_kept;
  j["seconds_field"] = s.seconds_field;
  j["seconds_solve"] = s.seconds_solve;
  j["seconds_mesh"] = s.seconds_mesh;
  if (s.tiles > 1) {
    j["tiles"] = s.tiles;
    j["largest_tile_nodes"] = s.largest_tile_nodes;
    j["largest_join_nodes"] = s.largest_join_nodes;
  }
  return j;
}

void write_recon_report(const std::filesystem::path& path, const ReconResult& result) {
  write_json_report(path, recon_report_json(result));
}

}  // namespace hos::recon
