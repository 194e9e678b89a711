// Per-image exposure gains: photos of the same surface taken with different
// exposure differ by a factor. Estimated robustly from the mean colours of
// faces seen by several views, so a person walking through one photo or a
// specular highlight does not bias the gains.
#pragma once

#include <vector>

#include "core/reporter.h"
#include "texture/visibility.h"

namespace hos::texture {

// Multiplicative RGB gain per view that makes the views agree (geometric mean
// 1 per channel), so differences in exposure and white balance are undone.
// Per channel k, minimizes over faces f and view pairs (u, v) seeing f
// rho(log(C_fuk) + log(g_uk) - log(C_fvk) - log(g_vk)) with a Cauchy loss rho
// (Ceres), C the face's mean colour in the view.
std::vector<Eigen::Vector3f> estimate_exposure_gains(const FaceViewCandidates& candidates,
                                                     int num_views,
                                                     Reporter& reporter);

// Multiplies every candidate's mean colour by its view's gain.
void apply_exposure_gains(const std::vector<Eigen::Vector3f>& gains, FaceViewCandidates& candidates);

}  // namespace hos::texture
