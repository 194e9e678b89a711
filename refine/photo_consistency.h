// The photometric data term: for every vertex, the offset along its normal at
// which a small tangent patch looks the same in the photos that see it
// (zero-mean normalised cross-correlation, so exposure differences between
// photos do not matter), and how much to trust it.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/reporter.h"
#include "core/types.h"
#include "refine/refine_options.h"
#include "refine/views.h"

namespace hos::refine {

struct VertexTarget {
  float offset = 0.0f;  // along the vertex normal, scene units
  float weight = 0.0f;  // 0 = no target (not seen, textureless, ambiguous)
  float score = 0.0f;   // best ZNCC (meaningful where weight > 0)
};

// One search per vertex at pyramid level `level`. views[i].depth must hold
// the mesh's depth at that level (render_depths); visibility_tolerance is in
// scene units.
std::vector<VertexTarget> search_normal_offsets(const TriangleMesh& mesh,
                                                const std::vector<Eigen::Vector3f>& normals,
                                                const std::vector<RefineView>& views,
                                                int level,
                                                double visibility_tolerance,
                                                const RefineOptions& options,
                                                Reporter& reporter);

// The same for the listed vertices only; the others get no target.
std::vector<VertexTarget> search_normal_offsets(const TriangleMesh& mesh,
                                                const std::vector<Eigen::Vector3f>& normals,
                                                const std::vector<int>& vertices,
                                                const std::vector<RefineView>& views,
                                                int level,
                                                double visibility_tolerance,
                                                const RefineOptions& options,
                                                Reporter& reporter);

// Zero-mean normalised cross-correlation of two equally long sample vectors;
// nothing when either is flat (standard deviation below min_std).
std::optional<float> zncc(const std::vector<float>& a, const std::vector<float>& b, float min_std);

}  // namespace hos::refine
