// Checks the driver makes so that a run does not fail late for a reason it
// could see early: an output that cannot be written, a disk too small for
// the next stage (by its estimate in pipeline/stages.h), a damaged
// intermediate, and the photo fingerprint that must not see the pipeline's
// own files.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/reporter.h"
#include "pipeline/stage_paths.h"

namespace hos::pipeline {

// Warns when the disk holding folder has less room than needed bytes,
// naming the disk and the stage.
void warn_if_low_space(const std::filesystem::path& folder,
                       std::uintmax_t needed,
                       const std::string& stage,
                       Reporter& reporter);

// Copies the finished model to output atomically; a failure (full disk,
// read-only folder) is an OutputError naming output, the reason and the disk.
void copy_result(const std::filesystem::path& model, const std::filesystem::path& output);

// The paths inside photos that the pipeline itself writes (the output and
// the workspace when they are inside the photo folder): the photo
// fingerprint leaves them out, so writing them does not look like new photos.
std::vector<std::filesystem::path> pipeline_files_in_photos(const std::filesystem::path& photos,
                                                            const std::filesystem::path& output,
                                                            const std::filesystem::path& workspace);

// The hint added when a stage rejects its input that an earlier stage wrote
// (e.g. a file in the workspace damaged or edited by hand).
std::string damaged_intermediate_hint(const std::string& producer);

}  // namespace hos::pipeline
