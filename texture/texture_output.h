// What hos-texture writes for a texturing result: the model in the format
// of the output's extension, its preview (the level of detail a web page
// embeds: the run report) and the summary lines of the log.
#pragma once

#include <filesystem>

#include "core/reporter.h"
#include "texture/texture_mesh.h"
#include "texture/texture_options.h"

namespace hos::texture {

// Writes the model to output and, when options.preview_max_faces > 0, the
// preview beside it (preview_model_path). Throws OutputError.
void write_texture_outputs(const std::filesystem::path& output,
                           const TextureResult& result,
                           const TextureOptions& options,
                           Reporter& reporter);

// Faces, charts, atlas coverage, placement and seam figures as log lines.
void log_texture_summary(const TextureResult& result, Reporter& reporter);

}  // namespace hos::texture
