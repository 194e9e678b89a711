// The texture stage's figures as JSON (hos-texture --report FILE), for the
// pipeline's run record: counts, step times, exposure gains, seam jumps and
// the root-node matrix of the glTF.
#pragma once

#include <filesystem>
#include <string>

#include "texture/texture_mesh.h"

namespace hos::texture {

std::string texture_report_json(const TextureResult& result);
// Writes atomically; throws OutputError.
void write_texture_report(const std::filesystem::path& path, const TextureResult& result);

}  // namespace hos::texture
