// The texture stage's figures as JSON (hos-texture --report FILE,
// WS/texture/report.json in a pipeline run), for the run report: counts,
// step times, exposure gains, seam jumps before and after leveling, views
// per face and the root-node matrix of the glTF.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "texture/texture_mesh.h"

namespace hos::texture {

nlohmann::ordered_json texture_report_json(const TextureResult& result);
// Writes atomically; throws OutputError.
void write_texture_report(const std::filesystem::path& path, const TextureResult& result);

}  // namespace hos::texture
