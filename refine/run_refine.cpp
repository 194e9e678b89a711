#include "refine/run_refine.h"

#include <algorithm>

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
  // Scores of different levels do not compare (a finer level's patches see
  // finer texture): the last level's first and last rounds do. That is the
  // finest level unless max_seconds stopped the run before it.
  const auto last_level =
      std::find(s.round_levels.begin(), s.round_levels.end(), s.round_levels.empty() ? 0 : s.round_levels.back());
  const std::size_t first = static_cast<std::size_t>(last_level - s.round_levels.begin());
  reporter.info(format_message(
      "wrote ", output_path.string(), ": ", result.mesh.num_vertices(), " vertices, ", result.mesh.num_faces(),
      " faces (", s.split_edges, " edges split", s.face_budget_reached ? ", face budget reached" : "", "); ", s.rounds,
      " rounds, mean ZNCC at the last level ", s.round_scores.empty() ? 0.0 : s.round_scores[first], " -> ",
      s.round_scores.empty() ? 0.0 : s.round_scores.back(), ", mean displacement ", s.mean_displacement, ", ",
      s.seconds, " s", s.out_of_time ? " (time budget reached)" : ""));
  return s;
}

}  // namespace hos::refine
