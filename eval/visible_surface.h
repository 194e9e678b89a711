// The part of a true surface the photos saw. Completeness against faces no
// camera saw (the underside of an object, the inside of a gap) measures the
// camera placement, not the reconstruction; benchmarks such as DTU and ETH3D
// restrict their truth to observed surface for the same reason.
#pragma once

#include "core/reporter.h"
#include "core/sparse_model.h"
#include "core/types.h"

namespace hos::eval {

// Faces of truth that cover at least one pixel centre, depth-tested against
// the whole truth, in at least min_views cameras of model (in truth's frame).
TriangleMesh visible_part(const TriangleMesh& truth, const SparseModel& model, int min_views, Reporter& reporter);

}  // namespace hos::eval
