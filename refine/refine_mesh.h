// hos-refine's library: moves a mesh's vertices along their normals until
// the photos agree on the surface, regularised by a thin-plate energy
// (regularizer.h), coarse to fine over image scales and mesh resolution:
// before each level, edges longer than a few pixels of the level are split
// (edge_split.h), within a face budget. Splitting and moving without
// fold-overs keep the mesh manifold.
#pragma once

#include <vector>

#include "core/reporter.h"
#include "core/types.h"
#include "core/undistorted_workspace.h"
#include "refine/refine_options.h"
#include "refine/views.h"

namespace hos::refine {

struct RefineStats {
  int rounds = 0;                      // rounds run over all levels
  std::vector<double> round_scores;    // mean best ZNCC of the vertices with a target, per round
  std::vector<int> round_levels;       // the pyramid level of each round (finer levels score lower)
  std::vector<double> round_searched;  // fraction of the vertices searched, per round (the rest filled in)
  double targeted_fraction = 0.0;      // vertices with a target in the last round
  double mean_displacement = 0.0;      // mean |final - input| over the input's vertices, scene units
  int folds_prevented = 0;             // vertices whose step was shortened to keep faces from flipping
  int split_edges = 0;                 // edges split to reach refine.edge_pixels
  bool face_budget_reached = false;    // refine.max_faces stopped the splitting
  bool out_of_time = false;            // stopped by max_seconds
  double seconds = 0.0;
};

struct RefineResult {
  TriangleMesh mesh;
  RefineStats stats;
};

// Refines input against views (each with options.levels pyramid levels).
// Throws Cancelled, NumericalError.
RefineResult refine_mesh(const TriangleMesh& input,
                         std::vector<RefineView> views,
                         const RefineOptions& options,
                         Reporter& reporter);

// The same with the photos of an undistorted workspace. Throws InputError
// for an unreadable photo or a mesh without faces (naming mesh_source).
RefineResult refine_mesh(const TriangleMesh& mesh,
                         const std::string& mesh_source,
                         const UndistortedWorkspace& workspace,
                         const RefineOptions& options,
                         Reporter& reporter);

}  // namespace hos::refine
