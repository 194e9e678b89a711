// Whether the photos support an estimated principal point. The bundle
// adjustment that frees the principal points always fits the keypoints a
// little better, also when the true principal point is the image centre, and
// a principal point moved by noise alone shifts every depth the later stages
// measure. An estimate is kept only when the fit improves by more than
// freeing that many parameters does by chance: a likelihood-ratio test of the
// two nested least-squares fits, the noise measured by the free fit.
#pragma once

#include <cstdint>
#include <map>

#include "core/sparse_model.h"

namespace hos::sfm {

// The squared reprojection errors of the keypoints with 3D points in the
// photos of one camera.
struct ReprojectionFit {
  double sum_squared_px = 0.0;    // over both image axes
  std::int64_t observations = 0;  // keypoints with a 3D point in front of their camera
};
// Each camera's fit (by camera id; a camera without such keypoints has none),
// in one pass over the model's points.
std::map<int, ReprojectionFit> reprojection_fits(const SparseModel& model);

// The chance probability below which an improvement counts as evidence: one
// set of photos in a thousand keeps a principal point that noise moved.
inline constexpr double kPrincipalPointSignificance = 0.001;

struct PrincipalPointEvidence {
  double chi_square = 0.0;  // the improvement over the noise variance per residual
  double chance = 1.0;      // probability of at least that improvement from noise alone
  bool supported = false;   // chance < kPrincipalPointSignificance
};

// centred: a camera's fit with its principal point at the image centre (as
// the mapper leaves it); estimated: its fit after the adjustment with the
// principal point free, which adds freed_parameters (two) to the fit.
PrincipalPointEvidence principal_point_evidence(const ReprojectionFit& centred,
                                                const ReprojectionFit& estimated,
                                                int freed_parameters);

// P(X >= x) for X chi-square distributed with an even number of degrees of
// freedom (closed form).
double chi_square_tail_even(double x, int degrees_of_freedom);

}  // namespace hos::sfm
