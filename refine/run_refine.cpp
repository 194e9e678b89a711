#include "refine/run_refine.h"

#include "core/ply_io.h"
#include "core/undistorted_workspace.h"

namespace hos::refine {

RefineStats run_refine(const std::filesystem::path& mesh_path,
                       const std::filesystem::path& workspace_path,
                       const std::filesystem::path& output_path,
                       const RefineOptions& options,
                       Reporter& reporter) {
  options.validate();
  const TriangleMesh mesh = read_mesh_ply(mesh_path);
  if (!options.enabled) {
    reporter.info("refine.enabled is false: the mesh passes through unchanged");
    write_mesh_ply(output_path, mesh);
    return {};
  }
  const UndistortedWorkspace workspace = load_undistorted_workspace(workspace_path);
  const RefineResult result = refine_mesh(mesh, mesh_path.string(), workspace, options, reporter);
  write_mesh_ply(output_path, result.mesh);
  const RefineStats& s = result.stats;
  reporter.info(format_message(
      "wrote ", output_path.string(), ": ", result.mesh.num_vertices(), " vertices, ", result.mesh.num_faces(),
      " faces (", s.split_edges, " edges split", s.face_budget_reached ? ", face budget reached" : "", "); ", s.rounds,
      " rounds, mean ZNCC ", s.round_scores.empty() ? 0.0 : s.round_scores.front(), " -> ",
      s.round_scores.empty() ? 0.0 : s.round_scores.back(), ", mean displacement ", s.mean_displacement, ", ",
      s.seconds, " s", s.out_of_time ? " (time budget reached)" : ""));
  return s;
}

}  // namespace hos::refine
