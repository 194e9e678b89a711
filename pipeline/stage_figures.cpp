#include "pipeline/stage_figures.h"

#include <cstring>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "core/error.h"
#include "pipeline/stage_paths.h"
#include "pipeline/stages.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

std::uint32_t le32(const unsigned char* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
}

}  // namespace

std::map<std::string, std::int64_t> ply_element_counts(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), "cannot be opened");
  std::string line;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0) throw InputError(file.string(), "not a PLY file");
  std::map<std::string, std::int64_t> counts;
  for (int i = 0; i < 1000 && std::getline(in, line); ++i) {
    if (line.rfind("end_header", 0) == 0) return counts;
    std::istringstream words(line);
    std::string keyword, name;
    std::int64_t count = 0;
    if (words >> keyword >> name >> count && keyword == "element") counts[name] = count;
  }
  throw InputError(file.string(), "PLY header has no end_header");
}

GlbFigures read_glb_figures(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), "cannot be opened");
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 20 || std::memcmp(bytes.data(), "glTF", 4) != 0) {
    throw InputError(file.string(), "not a binary glTF (.glb) file");
  }
  GlbFigures out;
  out.bytes = static_cast<std::int64_t>(bytes.size());
  const std::uint32_t json_length = le32(&bytes[12]);
  if (20 + std::size_t(json_length) > bytes.size()) throw InputError(file.string(), "truncated glTF JSON chunk");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(bytes.begin() + 20, bytes.begin() + 20 + json_length);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file.string(), std::string("invalid glTF JSON: ") + e.what());
  }
  const auto& nodes = j.value("nodes", nlohmann::json::array());
  if (!nodes.empty() && nodes[0].contains("matrix") && nodes[0]["matrix"].size() == 16) {
    for (std::size_t i = 0; i < 16; ++i) out.root_matrix[i] = nodes[0]["matrix"][i].get<double>();
  }
  // Binary chunk follows the (4-byte aligned) JSON chunk.
  const std::size_t bin_header = 20 + json_length;
  const std::size_t bin_start = bin_header + 8;
  const auto& accessors = j.value("accessors", nlohmann::json::array());
  for (const auto& mesh : j.value("meshes", nlohmann::json::array())) {
    for (const auto& prim : mesh.value("primitives", nlohmann::json::array())) {
      const auto& attributes = prim.value("attributes", nlohmann::json::object());
      if (attributes.contains("POSITION")) {
        const std::size_t a = attributes["POSITION"].get<std::size_t>();
        if (a < accessors.size()) out.vertices += accessors[a].value("count", std::int64_t{0});
      }
      if (prim.contains("indices")) {
        const std::size_t a = prim["indices"].get<std::size_t>();
        if (a < accessors.size()) out.triangles += accessors[a].value("count", std::int64_t{0}) / 3;
      }
    }
  }
  const auto& views = j.value("bufferViews", nlohmann::json::array());
  for (const auto& image : j.value("images", nlohmann::json::array())) {
    if (!image.contains("bufferView")) continue;
    const std::size_t v = image["bufferView"].get<std::size_t>();
    if (v >= views.size()) continue;
    const std::size_t offset = bin_start + views[v].value("byteOffset", std::size_t{0});
    const std::size_t length = views[v].value("byteLength", std::size_t{0});
    if (offset + length > bytes.size()) continue;
    const cv::Mat encoded(1, static_cast<int>(length), CV_8UC1, bytes.data() + offset);
    const cv::Mat decoded = cv::imdecode(encoded, cv::IMREAD_UNCHANGED);
    if (!decoded.empty()) out.texture_sizes.emplace_back(decoded.cols, decoded.rows);
  }
  return out;
}

nlohmann::json read_json_or_empty(const fs::path& file) {
  std::ifstream in(file);
  if (!in) return nlohmann::json::object();
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return nlohmann::json::object();
  }
}

nlohmann::ordered_json stage_figures(const std::string& stage, const fs::path& workspace) {
  nlohmann::ordered_json f = nlohmann::ordered_json::object();
  const StageSpec* spec = find_stage(stage);
  if (!spec) return f;
  try {
    spec->read_figures(StagePaths(workspace), f);
  } catch (const std::exception&) {
    // Figures are informative only; a stage's own checks decide success.
  }
  return f;
}

std::string figures_text(const std::string& stage, const nlohmann::ordered_json& f) {
  if (f.empty()) return "";
  const StageSpec* spec = find_stage(stage);
  return spec ? spec->figures_text(f) : f.dump();
}

}  // namespace hos::pipeline
