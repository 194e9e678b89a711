// Removing surface that the data does not support. The implicit function is
// defined everywhere, so its isosurface closes over areas without samples
// (the bottom of a scene, the far side of an open scan); photogrammetry users
// expect those bridges to be cut away.
#pragma once

#include <vector>

#include "core/types.h"

namespace hos::recon {

// Removes faces whose three vertices are all farther than max_distance from
// every sample, then unreferenced vertices; returns the faces removed. With
// sparse_reach above 1, around a sample with sparse but consistent support
// (fewer than 4 others within max_distance, at least 4 within sparse_reach
// times it) the distance is sparse_reach times longer, so surface that few
// samples cover keeps its mesh between them; an isolated sample keeps
// max_distance.
// Small pieces the cut leaves are debris (debris.h).
std::size_t trim_far_from_samples(TriangleMesh& mesh,
                                  const std::vector<Eigen::Vector3f>& samples,
                                  double max_distance,
                                  double sparse_reach = 1.0);

// Drops vertices no face uses, renumbering faces (keeps per-vertex attributes).
// Returns each old vertex's new index (-1: dropped), #old V.
std::vector<int> remove_unreferenced_vertices(TriangleMesh& mesh);

}  // namespace hos::recon
