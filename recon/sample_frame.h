// The samples a reconstruction works on, made independent of the input's
// scale and position and of a few far outliers: every step after this sees
// points in a unit frame (centred, longest extent 1), so no absolute length
// (a floor, an epsilon, a grid size) depends on the units of the input.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "core/types.h"

namespace hos::recon {

// world = center + scale * unit.
struct SampleFrame {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double scale = 1.0;

  Eigen::Vector3d to_world(const Eigen::Vector3d& unit) const { return center + scale * unit; }
};

struct OrientedSamples {
  std::vector<Eigen::Vector3f> points;   // N, in the unit frame
  std::vector<Eigen::Vector3f> normals;  // N, unit length
  std::vector<float> weights;            // N confidences (>= 0), or empty: all 1
  SampleFrame frame;
  std::size_t dropped_without_normal = 0;  // non-finite position or no usable normal
  std::size_t dropped_far = 0;             // far outliers (see prepare_samples)
};

// The oriented samples of input in their unit frame. Points without a finite
// position or a non-zero finite normal are dropped (normals are normalised
// in double, so a length of 1e38 is fine). Far outliers are dropped: points
// farther than the robust extent (the 1st to 99th percentile per axis) from
// the robust box, so one stray point cannot make the domain huge and the
// object a few voxels wide. Throws InputError(source, ...) when nothing is
// left or the extent is zero or below numerical resolution.
OrientedSamples prepare_samples(const PointCloud& input, bool use_confidence, const std::string& source);

// Throws InputError(source, ...) when box (of float points) has a longest
// extent that is zero, not finite, or too small to resolve relative to its
// distance from the origin (float has 24 bits).
void check_extent(const BoundingBox& box, const std::string& source);

// A mesh or a grid found in the unit frame, moved back to the world.
void to_world(const SampleFrame& frame, TriangleMesh& mesh);

}  // namespace hos::recon
