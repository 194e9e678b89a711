#include "sfm/principal_point_evidence.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <vector>

namespace hos::sfm {

std::map<int, ReprojectionFit> reprojection_fits(const SparseModel& model) {
  std::map<int, ReprojectionFit> fits;
  for (const auto& [id, point] : model.points) {
    for (const TrackElement& element : point.track) {
      const auto image = model.images.find(element.image_id);
      if (image == model.images.end()) continue;
      const ImageRecord& record = image->second;
      if (element.keypoint_index < 0 || element.keypoint_index >= static_cast<int>(record.keypoints.size())) continue;
      const auto pixel = model.camera_of(record).project(record.cam_from_world(point.xyz));
      if (!pixel) continue;
      ReprojectionFit& fit = fits[record.camera_id];
      fit.sum_squared_px += (*pixel - record.keypoints[element.keypoint_index].xy).squaredNorm();
      ++fit.observations;
    }
  }
  return fits;
}

double chi_square_tail_even(double x, int degrees_of_freedom) {
  if (degrees_of_freedom <= 0 || degrees_of_freedom % 2 != 0) {
    throw std::invalid_argument("chi_square_tail_even: degrees of freedom must be even and positive");
  }
  if (x <= 0.0) return 1.0;
  // exp(-x/2) * sum_{i < k/2} (x/2)^i / i!, its terms summed in log space so
  // that many cameras (large k and x) neither overflow nor underflow.
  const double half = 0.5 * x;
  const int terms = degrees_of_freedom / 2;
  double log_largest = -half;
  std::vector<double> log_terms(terms);
  for (int i = 0; i < terms; ++i) {
    log_terms[i] = -half + i * std::log(half) - std::lgamma(i + 1.0);
    log_largest = std::max(log_largest, log_terms[i]);
  }
  double sum = 0.0;
  for (const double t : log_terms) sum += std::exp(t - log_largest);
  return std::min(1.0, std::exp(log_largest) * sum);
}

PrincipalPointEvidence principal_point_evidence(const ReprojectionFit& centred,
                                                const ReprojectionFit& estimated,
                                                int freed_parameters) {
  PrincipalPointEvidence evidence;
  const std::int64_t residuals = 2 * estimated.observations;
  if (freed_parameters <= 0 || residuals <= freed_parameters) return evidence;
  const double improvement = centred.sum_squared_px - estimated.sum_squared_px;
  if (improvement <= 0.0) return evidence;
  // Residual variance of the free fit; an exact fit leaves no noise, so any
  // improvement is evidence.
  const double variance = estimated.sum_squared_px / static_cast<double>(residuals - freed_parameters);
  if (variance <= 0.0) {
    evidence.chance = 0.0;
    evidence.chi_square = HUGE_VAL;
    evidence.supported = true;
    return evidence;
  }
  evidence.chi_square = improvement / variance;
  evidence.chance = chi_square_tail_even(evidence.chi_square, freed_parameters);
  evidence.supported = evidence.chance < kPrincipalPointSignificance;
  return evidence;
}

}  // namespace hos::sfm
