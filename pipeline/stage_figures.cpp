#include "pipeline/stage_figures.h"

#include <cstring>
#include <fstream>
#include <iomanip>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "core/error.h"
#include "pipeline/stage_paths.h"

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

namespace {

// The keys a stage's report.json has, copied into f (none if it cannot be read).
void copy_report_figures(const fs::path& report, std::initializer_list<const char*> keys, nlohmann::ordered_json& f) {
  std::ifstream in(report);
  if (!in) return;
  const nlohmann::json r = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!r.is_object()) return;
  for (const char* key : keys) {
    if (r.contains(key)) f[key] = r[key];
  }
}

}  // namespace

nlohmann::ordered_json stage_figures(const std::string& stage, const fs::path& workspace) {
  const StagePaths paths(workspace);
  nlohmann::ordered_json f = nlohmann::ordered_json::object();
  try {
    if (stage == "sfm") {
      std::ifstream in(paths.sfm_report);
      // Ordered, so the steps keep the order they ran in.
      const nlohmann::ordered_json r = nlohmann::ordered_json::parse(in);
      for (const char* key : {"images_registered", "images_given", "points", "mean_reprojection_error_px",
                              "mean_track_length", "matcher", "step_seconds"}) {
        if (r.contains(key)) f[key] = r[key];
      }
    } else if (stage == "mvs") {
      f["points"] = ply_element_counts(paths.points)["vertex"];
    } else if (stage == "recon" || stage == "refine") {
      auto counts = ply_element_counts(stage == "recon" ? paths.mesh : paths.refined_mesh);
      f["vertices"] = counts["vertex"];
      f["faces"] = counts["face"];
      if (stage == "recon")
        copy_report_figures(paths.recon_report, {"debris_pieces_removed", "debris_area_removed", "surface_area"}, f);
    } else if (stage == "texture") {
      copy_report_figures(paths.texture_report, {"unseen_faces"}, f);
      const GlbFigures g = read_glb_figures(paths.textured_model);
      f["bytes"] = g.bytes;
      f["vertices"] = g.vertices;
      f["triangles"] = g.triangles;
      nlohmann::ordered_json sizes = nlohmann::ordered_json::array();
      for (const auto& [w, h] : g.texture_sizes) sizes.push_back(std::to_string(w) + "x" + std::to_string(h));
      f["textures"] = sizes;
      // How the model is placed: "units: metres from GPS (...)" or why the units are arbitrary.
      std::ifstream in(paths.texture_report);
      const nlohmann::json report = nlohmann::json::parse(in, nullptr, false);
      if (report.is_object() && report.contains("placement") && report["placement"].contains("units_text")) {
        f["units"] = report["placement"]["units_text"];
      }
    }
  } catch (const std::exception&) {
    // Figures are informative only; a stage's own checks decide success.
  }
  return f;
}

std::string figures_text(const std::string& stage, const nlohmann::ordered_json& f) {
  if (f.empty()) return "";
  auto num = [&](const char* key) { return f.contains(key) ? f[key].dump() : std::string("?"); };
  std::ostringstream text;
  if (stage == "sfm") {
    text << num("images_registered") << "/" << num("images_given") << " images registered, " << num("points")
         << " points";
    if (f.contains("matcher")) text << ", " << f["matcher"].get<std::string>() << " matching";
    if (f.contains("step_seconds")) {
      // The COLMAP steps' times, so a slow step shows in the summary.
      text << std::fixed << std::setprecision(1);
      for (const auto& [step, seconds] : f["step_seconds"].items())
        text << "; " << step << " " << seconds.get<double>() << " s";
    }
  } else if (stage == "mvs") {
    text << num("points") << " dense points";
  } else if (stage == "recon" || stage == "refine") {
    text << num("vertices") << " vertices, " << num("faces") << " faces";
    if (f.contains("debris_pieces_removed") && f["debris_pieces_removed"].get<std::int64_t>() > 0) {
      text << "; " << num("debris_pieces_removed") << " debris pieces removed";
      const double removed = f.value("debris_area_removed", 0.0), kept = f.value("surface_area", 0.0);
      if (removed + kept > 0.0)
        text << " (" << std::setprecision(2) << 100.0 * removed / (removed + kept) << "% of the area)";
    }
  } else if (stage == "texture") {
    text << num("triangles") << " triangles";
    if (f.contains("unseen_faces") && f["unseen_faces"].get<std::int64_t>() > 0) {
      text << ", " << num("unseen_faces") << " faces seen by no photo";
    }
    if (f.contains("textures") && !f["textures"].empty()) {
      text << ", texture";
      for (const auto& s : f["textures"]) text << " " << s.get<std::string>();
    }
    if (f.contains("units")) text << "; " << f["units"].get<std::string>();
  } else {
    text << f.dump();
  }
  return text.str();
}

}  // namespace hos::pipeline
