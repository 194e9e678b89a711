// View selection per face as a labelling problem (Waechter et al. 2014,
// Sec. 4): data term from the gradient-magnitude integral weighted by the
// viewing angle, Potts smoothness between edge-adjacent faces, minimized by
// alpha-expansion with Boykov-Kolmogorov max-flow (Debian's libmaxflow).
#pragma once

#include <vector>

#include "core/reporter.h"
#include "texture/mesh_topology.h"
#include "texture/texture_options.h"
#include "texture/visibility.h"

namespace hos::texture {

// Photo-consistency check (Waechter Sec. 4, outlier removal): per face with at
// least options.outlier_min_views views, the mode of the views' mean colours
// is found by mean shift from the median; views farther than
// options.outlier_threshold are removed from the candidates. Returns the
// number of removed (face, view) pairs. Never removes all views of a face.
std::int64_t reject_outlier_views(FaceViewCandidates& candidates, const TextureOptions& options);

struct ViewSelection {
  std::vector<int> labels;  // view per face, -1 if no view sees the face
  int num_unseen = 0;
  double data_energy = 0.0;
  double smoothness_energy = 0.0;
};

// Data cost of a candidate in [0, 1]: 1 - quality / best quality of the face.
std::vector<float> data_costs(const FaceViewCandidates& candidates, const TextureOptions& options);

ViewSelection select_views(const MeshTopology& topology,
                           const FaceViewCandidates& candidates,
                           const TextureOptions& options,
                           Reporter& reporter);

}  // namespace hos::texture
