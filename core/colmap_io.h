// Reading and writing COLMAP sparse models (cameras, images, points3D) in
// COLMAP's binary (.bin) and text (.txt) formats.
#pragma once

#include <filesystem>

#include "core/sparse_model.h"

namespace hos {

enum class ColmapFormat { kBinary, kText };

// Reads a model from a folder holding cameras/images/points3D as .bin or .txt
// (binary preferred when both exist). Throws InputError naming the missing or
// malformed file.
SparseModel read_colmap_model(const std::filesystem::path& folder);
SparseModel read_colmap_model_binary(const std::filesystem::path& folder);
SparseModel read_colmap_model_text(const std::filesystem::path& folder);

// Writes the three files into folder (created if missing). Throws OutputError.
void write_colmap_model(const SparseModel& model, const std::filesystem::path& folder, ColmapFormat format);

}  // namespace hos
