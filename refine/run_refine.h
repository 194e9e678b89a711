// hos-refine's job on files: the recon mesh and the undistorted workspace in,
// the refined mesh out (written atomically). With refine.enabled false the
// mesh passes through unchanged, so the next stage always reads this stage's
// output and the pipeline's fingerprints stay simple.
#pragma once

#include <filesystem>

#include "core/reporter.h"
#include "refine/refine_mesh.h"
#include "refine/refine_options.h"

namespace hos::refine {

// Throws InputError (mesh or workspace missing or malformed), OutputError,
// Cancelled, NumericalError.
RefineStats run_refine(const std::filesystem::path& mesh_path,
                       const std::filesystem::path& workspace_path,
                       const std::filesystem::path& output_path,
                       const RefineOptions& options,
                       Reporter& reporter);

}  // namespace hos::refine
