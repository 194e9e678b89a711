#include "pipeline/report_viewer.h"

#include <Eigen/Core>
#include <fstream>
#include <sstream>

#include "core/colmap_io.h"
#include "core/error.h"
#include "pipeline/stage_figures.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

// The bundle without its source-map comment (the map is not shipped).
std::string viewer_script_text(const fs::path& script) {
  std::string text = read_bytes(script);
  const auto map = text.rfind("//# sourceMappingURL=");
  if (map != std::string::npos) text.erase(map);
  return text;
}

// Camera centres in the model's coordinates: the glb's root transform
// applied to the sfm centres (-R^T t), as the mesh's vertices are.
std::vector<Eigen::Vector3d> camera_centres(const StagePaths& paths, const std::array<double, 16>& root) {
  std::vector<Eigen::Vector3d> centres;
  SparseModel model;
  try {
    model = read_colmap_model(paths.undistorted / "sparse");
  } catch (const Error&) {
    return centres;
  }
  const Eigen::Map<const Eigen::Matrix4d> matrix(root.data());
  for (const auto& [id, image] : model.images) {
    centres.push_back((matrix * image.center().homogeneous()).hnormalized());
  }
  return centres;
}

constexpr const char* kViewerStyle = R"(<style>
#viewer { width: 100%; height: 520px; background: #ffffff; }
#viewer .camera { width: 9px; height: 9px; border-radius: 50%; border: none; padding: 0;
                  background: #e0322f; box-shadow: 0 0 0 1px #fff; }
#viewer.hide-cameras .camera { display: none; }
</style>)";

}  // namespace

fs::path default_viewer_script(const fs::path& bin_dir) {
  return bin_dir.parent_path() / "share" / "hos" / "model-viewer-umd.min.js";
}

std::string model_viewer_html(const StagePaths& paths, const fs::path& viewer_script) {
  std::error_code ec;
  if (!fs::is_regular_file(paths.textured_model, ec)) return "";
  std::ostringstream html;
  html << "<h2>Model</h2>\n";
  if (viewer_script.empty() || !fs::is_regular_file(viewer_script, ec)) {
    html << "<p id=\"model\"><a href=\"texture/model.glb\">texture/model.glb</a> (this build has "
            "no 3D viewer)</p>\n";
    return html.str();
  }
  GlbFigures glb;
  try {
    glb = read_glb_figures(paths.textured_model);
  } catch (const Error&) {
    html << "<p id=\"model\">texture/model.glb is not a valid binary glTF.</p>\n";
    return html.str();
  }
  html << kViewerStyle << "\n<model-viewer id=\"viewer\" camera-controls alt=\"the textured model\" "
       << "src=\"data:model/gltf-binary;base64," << base64(read_bytes(paths.textured_model)) << "\">\n";
  int index = 0;
  for (const Eigen::Vector3d& c : camera_centres(paths, glb.root_matrix)) {
    ++index;
    html << "<button class=\"camera\" slot=\"hotspot-camera-" << index << "\" data-position=\"" << c.x() << " " << c.y()
         << " " << c.z() << "\" title=\"camera " << index << "\"></button>\n";
  }
  html << "</model-viewer>\n<p><label><input type=\"checkbox\" id=\"show-cameras\" checked> show "
          "the "
       << index << " camera positions</label> · <a href=\"texture/model.glb\">texture/model.glb</a></p>\n";
  html << "<script>\n" << viewer_script_text(viewer_script) << "\n</script>\n";
  html << "<script>\ndocument.getElementById('show-cameras').addEventListener('change', (e) =>\n"
          "  document.getElementById('viewer').classList.toggle('hide-cameras', "
          "!e.target.checked));\n</script>\n";
  return html.str();
}

std::string read_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

std::string base64(const std::string& bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 3; ++k) v = (v << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kAlphabet[(v >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

}  // namespace hos::pipeline
