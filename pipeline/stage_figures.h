// Key figures of each stage's output, read cheaply from the files (headers,
// not the whole data) for run.json and the summary table; each stage's own
// are in its entry of the stage table (pipeline/stages.h).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

namespace hos::pipeline {

// Element counts from a PLY header ("vertex" -> 12000, "face" -> 24000).
// Throws InputError if the file is missing or has no valid PLY header.
std::map<std::string, std::int64_t> ply_element_counts(const std::filesystem::path& file);

struct GlbFigures {
  std::int64_t bytes = 0;
  std::int64_t vertices = 0;                       // sum of POSITION accessor counts
  std::int64_t triangles = 0;                      // sum of index counts / 3
  std::vector<std::pair<int, int>> texture_sizes;  // width, height of each image
  // The first node's transform (column-major; identity when it has none):
  // model coordinates of the scene's points.
  std::array<double, 16> root_matrix{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
};
// Throws InputError if the file is not a binary glTF.
GlbFigures read_glb_figures(const std::filesystem::path& file);

// The JSON in file, or an empty object if it is missing or not JSON (a stage
// that did not finish has written no report).
nlohmann::json read_json_or_empty(const std::filesystem::path& file);

// Figures of one stage from its outputs in the workspace (an empty object if
// the outputs cannot be read).
nlohmann::ordered_json stage_figures(const std::string& stage, const std::filesystem::path& workspace);
// One line for the summary table, e.g. "16/16 images, 4210 points".
std::string figures_text(const std::string& stage, const nlohmann::ordered_json& figures);

}  // namespace hos::pipeline
