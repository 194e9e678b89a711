// Per-image exposure gains: photos of the same surface taken with different
// exposure differ by a factor. Estimated robustly from the mean colours of
// faces seen by several views, so a person walking through one photo or a
// specular highlight does not bias the gains.
#pragma once

#include <vector>

#include "core/reporter.h"
#include "texture/visibility.h"

namespace hos {

// Multiplicative gain per view that makes the views agree (geometric mean 1).
// Minimizes sum over faces f and view pairs (u, v) seeing f of
// rho(log(L_fu) + log(g_u) - log(L_fv) - log(g_v)) with a Cauchy loss rho
// (Ceres), L the face's mean luminance.
std::vector<float> estimate_exposure_gains(const FaceViewCandidates& candidates, int num_views,
                                           Reporter& reporter);

// Multiplies every candidate's mean colour by its view's gain.
void apply_exposure_gains(const std::vector<float>& gains, FaceViewCandidates& candidates);

}  // namespace hos
