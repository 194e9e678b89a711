// Which views see which faces, with a per-view depth buffer (real occlusion,
// not only back-face culling), and what each view sees of each face: the
// visible pixel count, the integral of the gradient magnitude and the mean
// colour over the visible projected face (inputs of view selection).
#pragma once

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "core/reporter.h"
#include "core/types.h"
#include "texture/mesh_topology.h"
#include "texture/texture_options.h"
#include "texture/texture_view.h"

namespace hos::texture {

struct FaceViewSample {
  int view = 0;
  float gradient_integral = 0.0f;  // sum of |grad I| over visible pixels (grey levels)
  float visible_px = 0.0f;         // pixels whose nearest surface is the face
  float projected_area_px = 0.0f;
  float cos_angle = 0.0f;                              // between face normal and direction to the camera
  Eigen::Vector3f mean_rgb = Eigen::Vector3f::Zero();  // 8-bit scale
};

// Candidates of every face, CSR: samples[offsets[f] .. offsets[f+1]).
struct FaceViewCandidates {
  std::vector<int> offsets;
  std::vector<FaceViewSample> samples;

  int num_faces() const { return offsets.empty() ? 0 : static_cast<int>(offsets.size()) - 1; }
  int begin(int f) const { return offsets[f]; }
  int end(int f) const { return offsets[f + 1]; }
};

// What one view sees: (face, sample) pairs in increasing face order.
using ViewSamples = std::vector<std::pair<int, FaceViewSample>>;

// The visibility of one view, views[view_index] of the run (the samples
// carry that index). The per-view part of compute_visibility: split runs
// compute it for a range of views in separate processes.
ViewSamples compute_view_visibility(const TriangleMesh& mesh,
                                    const MeshTopology& topology,
                                    const TextureView& view,
                                    int view_index,
                                    const TextureOptions& options);

// The candidates of every face from the samples of every view, in view
// order (per_view[v] holds view v's); per_view is emptied as it is read.
FaceViewCandidates gather_candidates(int num_faces, std::vector<ViewSamples>& per_view);

// Rasterizes the mesh into a depth/face-id buffer per view and keeps a
// (face, view) pair if the face points at the camera within
// options.max_view_angle_deg, lies inside the image, and its centroid and three
// inner points pass the depth test (relative tolerance options.depth_tolerance).
FaceViewCandidates compute_visibility(const TriangleMesh& mesh,
                                      const MeshTopology& topology,
                                      const std::vector<TextureView>& views,
                                      const TextureOptions& options,
                                      Reporter& reporter);

}  // namespace hos::texture
