#include "pipeline/report/report_viewer.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "core/colmap_io.h"
#include "core/error.h"
#include "core/glb_container.h"
#include "core/json_report.h"
#include "core/ply_io.h"
#include "core/statistics.h"
#include "pipeline/report/svg_plot.h"
#include "pipeline/stage_figures.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

// The largest model the page embeds (base64 adds a third): with
// model-viewer's script (about 1 MB), the thumbnails and the rest, the page
// stays under 8 MB.
constexpr std::uintmax_t kMaxEmbeddedModelBytes = 4'500'000;

std::string megabytes(std::uintmax_t bytes) {
  std::ostringstream out;
  out.precision(3);
  out << double(bytes) / 1e6 << " MB";
  return out.str();
}

// The model the viewer shows: hos-texture's preview beside the model,
// else the model itself; neither when larger than the page can hold.
std::optional<fs::path> model_to_embed(const StagePaths& paths) {
  for (const fs::path& model : {report_preview_model(paths), paths.textured_model}) {
    std::error_code ec;
    if (fs::is_regular_file(model, ec) && fs::file_size(model, ec) <= kMaxEmbeddedModelBytes && !ec) return model;
  }
  return std::nullopt;
}

// The bundle without its source-map comment (the map is not shipped).
std::string viewer_script_text(const fs::path& script) {
  std::string text = read_bytes(script);
  const auto map = text.rfind("//# sourceMappingURL=");
  if (map != std::string::npos) text.erase(map);
  return text;
}

Eigen::Vector3d transform_point(const Eigen::Matrix4d& m, const Eigen::Vector3d& x) {
  return (m * x.homogeneous()).hnormalized();
}

// The surface the model was textured from (refined, else reconstructed).
std::vector<Eigen::Vector3f> surface_vertices(const StagePaths& paths) {
  for (const fs::path& mesh : {paths.refined_mesh, paths.mesh}) {
    std::error_code ec;
    if (!fs::is_regular_file(mesh, ec)) continue;
    try {
      return read_mesh_ply(mesh).vertices;
    } catch (const Error&) {
    }
  }
  return {};
}

nlohmann::json vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// What the page's script needs: every photo's view and frustum, and the
// robust bounds (frusta scale and zoom limits).
std::string viewer_data_json(const std::vector<PhotoView>& views, const RobustBounds& bounds) {
  nlohmann::json data;
  data["centre"] = vec(bounds.centre);
  data["size"] = bounds.size;
  data["cameras"] = nlohmann::json::array();
  for (const PhotoView& v : views) {
    nlohmann::json corners = nlohmann::json::array();
    for (const auto& c : v.corners) corners.push_back(vec(c));
    data["cameras"].push_back({{"name", v.name},
                               {"position", vec(v.position)},
                               {"direction", vec(v.direction)},
                               {"corners", corners},
                               {"target", vec(v.target)},
                               {"theta", v.theta},
                               {"phi", v.phi},
                               {"radius", v.radius},
                               {"fov_deg", v.vertical_fov_deg}});
  }
  // Inside <script type="application/json">: "</" must not end the element.
  std::string text = json_text(data, -1);  // photo names need not be UTF-8
  for (std::size_t at = text.find("</"); at != std::string::npos; at = text.find("</", at + 2))
    text.replace(at, 2, "<\\/");
  return text;
}

constexpr const char* kViewerStyle = R"(<style>
#viewer-frame { position: relative; width: 100%; max-width: min(100%, 140vh); }
#viewer { width: 100%; height: auto; background: #ffffff; display: block; }
#viewer-frusta { position: absolute; left: 0; top: 0; width: 100%; height: 100%; pointer-events: none; }
#viewer-frusta path { fill: rgba(224, 50, 47, 0.12); stroke: #e0322f; stroke-width: 1.5; pointer-events: all;
                      cursor: pointer; }
#viewer-frusta path:hover { fill: rgba(224, 50, 47, 0.45); }
#viewer-frame.hide-cameras #viewer-frusta { display: none; }
</style>)";

// Sets the first photo's view, compensating model-viewer's widening of the
// field of view for the model's aspect, records the camera the viewer then
// has in data-initial-camera (read by the report's browser test), and draws
// every photo's frustum each frame with the viewer's own camera; a click on
// one moves the view to that photo's.
constexpr const char* kViewerScript = R"JS(
(() => {
  const viewer = document.getElementById('viewer');
  const frame = document.getElementById('viewer-frame');
  const svg = document.getElementById('viewer-frusta');
  const data = JSON.parse(document.getElementById('viewer-data').textContent);
  const rad = Math.PI / 180;
  const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const unit = (a) => { const n = Math.hypot(a[0], a[1], a[2]) || 1; return [a[0] / n, a[1] / n, a[2] / n]; };
  // model-viewer's camera: on a sphere about the target, looking at it, +Y up.
  function cameraPose() {
    const o = viewer.getCameraOrbit(), t = viewer.getCameraTarget();
    const s = Math.sin(o.phi);
    const target = [t.x, t.y, t.z];
    const position = [t.x + o.radius * s * Math.sin(o.theta), t.y + o.radius * Math.cos(o.phi),
                      t.z + o.radius * s * Math.cos(o.theta)];
    return {position, direction: unit(sub(target, position)), fov_deg: viewer.getFieldOfView()};
  }
  let fovScale = 1;  // tan(shown / 2) / tan(asked / 2): model-viewer widens for the model's aspect
  function askFov(fovDeg) {
    return 2 * Math.atan(Math.tan(fovDeg * rad / 2) / fovScale) / rad;
  }
  function setView(cam) {
    viewer.cameraTarget = `${cam.target[0]}m ${cam.target[1]}m ${cam.target[2]}m`;
    viewer.cameraOrbit = `${cam.theta}rad ${cam.phi}rad ${cam.radius}m`;
    viewer.fieldOfView = `${askFov(cam.fov_deg)}deg`;
  }
  const nextFrame = () => new Promise((resolve) => requestAnimationFrame(() => resolve()));
  async function openFirstView() {
    const first = data.cameras[0];
    for (let round = 0; round < 3; ++round) {
      const asked = askFov(first.fov_deg);
      setView(first);
      await viewer.updateComplete;
      viewer.jumpCameraToGoal();
      await nextFrame();
      await nextFrame();
      const shown = viewer.getFieldOfView();
      if (Math.abs(shown - first.fov_deg) < 0.01) break;
      fovScale = Math.tan(shown * rad / 2) / Math.tan(asked * rad / 2);
    }
    viewer.dataset.initialCamera = JSON.stringify(cameraPose());
  }
  const paths = data.cameras.map((cam) => {
    const path = document.createElementNS('http://www.w3.org/2000/svg', 'path');
    const title = document.createElementNS('http://www.w3.org/2000/svg', 'title');
    title.textContent = cam.name;
    path.appendChild(title);
    path.addEventListener('click', () => setView(cam));
    svg.appendChild(path);
    return path;
  });
  function draw() {
    const pose = cameraPose();
    const w = viewer.clientWidth, h = viewer.clientHeight;
    const f = pose.direction;
    const right = unit(cross(f, [0, 1, 0])), up = cross(right, f);
    const focal = (h / 2) / Math.tan(pose.fov_deg * rad / 2);
    const near = 1e-6 * data.size;
    data.cameras.forEach((cam, i) => {
      const points = [cam.position, ...cam.corners].map((x) => {
        const v = sub(x, pose.position);
        const z = dot(v, f);
        return z > near ? [w / 2 + focal * dot(v, right) / z, h / 2 - focal * dot(v, up) / z] : null;
      });
      if (points.some((p) => p === null)) {
        paths[i].setAttribute('d', '');
        return;
      }
      const [a, ...c] = points.map((p) => `${p[0].toFixed(1)} ${p[1].toFixed(1)}`);
      paths[i].setAttribute('d', `M${c[0]} L${c[1]} L${c[2]} L${c[3]} Z M${a} L${c[0]} M${a} L${c[1]} M${a} L${c[2]} ` +
                                 `M${a} L${c[3]}`);
    });
    requestAnimationFrame(draw);
  }
  const start = () => {
    openFirstView();
    requestAnimationFrame(draw);
  };
  // The element loads as soon as the parser creates it: a small model may be
  // in before this script runs.
  if (viewer.dataset.loaded) start(); else viewer.addEventListener('load', start, {once: true});
  document.getElementById('show-cameras').addEventListener('change', (e) =>
    frame.classList.toggle('hide-cameras', !e.target.checked));
})();
)JS";

// Whether the .glb requires EXT_meshopt_compression, as the preview does; a
// name or extras that mention it do not count.
bool needs_meshopt_decoder(const std::string& glb, const fs::path& file) {
  const std::vector<std::string> required = glb_required_extensions(glb, file.string());
  return std::find(required.begin(), required.end(), "EXT_meshopt_compression") != required.end();
}

// model-viewer's bundle as a script element. A meshopt-compressed model (the
// preview: texture/texture_output.h) needs the bundle and where its meshopt
// decoder loads from before the element (the bundle holds the decoder and
// only waits for that script to load; it replaces ModelViewerElement when it
// runs). Other models keep the bundle after the element.
std::string bundle_scripts(const fs::path& viewer_script, bool meshopt) {
  std::string html = "<script>\n" + viewer_script_text(viewer_script) + "\n</script>\n";
  if (meshopt) html += "<script>self.ModelViewerElement.meshoptDecoderLocation = \"data:text/javascript,\";</script>\n";
  return html;
}

}  // namespace

fs::path default_viewer_script(const fs::path& bin_dir) {
  return bin_dir.parent_path() / "share" / "hos" / "model-viewer-umd.min.js";
}

std::optional<RobustBounds> robust_bounds(const std::vector<Eigen::Vector3f>& vertices, const Eigen::Matrix4d& root) {
  if (vertices.empty()) return std::nullopt;
  std::array<std::vector<double>, 3> axis;
  for (const Eigen::Vector3f& v : vertices) {
    const Eigen::Vector3d x = transform_point(root, v.cast<double>());
    if (!x.allFinite()) continue;
    for (int k = 0; k < 3; ++k) axis[k].push_back(x[k]);
  }
  if (axis[0].empty()) return std::nullopt;
  RobustBounds bounds;
  double size = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double low = quantile(axis[k], 0.02), high = quantile(axis[k], 0.98);
    bounds.centre[k] = 0.5 * (low + high);
    size = std::max(size, high - low);
  }
  if (size > 0.0) bounds.size = size;
  return bounds;
}

std::vector<PhotoView> photo_views(const SparseModel& model, const Eigen::Matrix4d& root, const RobustBounds& bounds) {
  std::vector<PhotoView> views;
  const Eigen::Matrix3d linear = root.topLeftCorner<3, 3>();
  for (const auto& [id, image] : model.images) {
    const auto camera = model.cameras.find(image.camera_id);
    if (camera == model.cameras.end() || camera->second.width <= 0 || camera->second.height <= 0) continue;
    const Camera& cam = camera->second;
    PhotoView view;
    view.name = image.name;
    const Eigen::Vector3d centre = image.center();
    view.position = transform_point(root, centre);
    view.direction = (linear * image.viewing_direction()).normalized();
    view.vertical_fov_deg = 2.0 * std::atan(0.5 * cam.height / cam.focal_y()) * 180.0 / std::numbers::pi;
    view.aspect = static_cast<double>(cam.width) / cam.height;
    const double w = cam.width, h = cam.height;
    const std::array<Eigen::Vector2d, 4> pixels = {Eigen::Vector2d(0, 0), Eigen::Vector2d(w, 0), Eigen::Vector2d(w, h),
                                                   Eigen::Vector2d(0, h)};
    const double depth = 0.05 * bounds.size;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d ray((pixels[k].x() - cam.principal_x()) / cam.focal_x(),
                                (pixels[k].y() - cam.principal_y()) / cam.focal_y(), 1.0);
      const Eigen::Vector3d along = linear * (image.rotation().transpose() * ray);
      // Scaled so the frustum is `depth` deep along the optical axis.
      view.corners[k] = view.position + along * (depth / along.dot(view.direction));
    }
    const double distance = std::max(view.direction.dot(bounds.centre - view.position), 0.1 * bounds.size);
    view.target = view.position + distance * view.direction;
    const Eigen::Vector3d offset = view.position - view.target;  // from the target to the camera
    view.radius = distance;
    view.theta = std::atan2(offset.x(), offset.z());
    view.phi = std::acos(std::clamp(offset.y() / distance, -1.0, 1.0));
    if (view.position.allFinite() && view.direction.allFinite()) views.push_back(view);
  }
  return views;
}

fs::path report_preview_model(const StagePaths& paths) {
  const fs::path& model = paths.textured_model;
  return model.parent_path() / (model.stem().string() + ".preview.glb");
}

std::string model_viewer_html(const StagePaths& paths, const fs::path& viewer_script) {
  std::error_code ec;
  if (!fs::is_regular_file(paths.textured_model, ec)) return "";
  const std::uintmax_t model_bytes = fs::file_size(paths.textured_model, ec);
  const std::string model_link =
      "<a id=\"model-link\" href=\"texture/model.glb\">texture/model.glb</a> (" + megabytes(model_bytes) + ")";
  std::ostringstream html;
  html << "<h2>Model</h2>\n";
  if (viewer_script.empty() || !fs::is_regular_file(viewer_script, ec)) {
    html << "<p id=\"model\">" << model_link << " (this build has no 3D viewer)</p>\n";
    return html.str();
  }
  const std::optional<fs::path> shown = model_to_embed(paths);
  if (!shown) {
    const fs::path preview = report_preview_model(paths);
    html << "<p id=\"model\">The model is too large to embed in this page ("
         << (fs::is_regular_file(preview, ec) ? "and so is its preview texture/" + preview.filename().string() + ", " +
                                                    megabytes(fs::file_size(preview, ec))
                                              : std::string("and it has no preview beside it"))
         << "; at most " << megabytes(kMaxEmbeddedModelBytes) << "): " << model_link << "</p>\n";
    return html.str();
  }
  const bool preview = *shown != paths.textured_model;
  const std::string shown_name = "texture/" + shown->filename().string();
  const std::string shown_bytes = read_bytes(*shown);
  GlbFigures glb;
  bool meshopt = false;
  try {
    glb = read_glb_figures(*shown);
    meshopt = needs_meshopt_decoder(shown_bytes, *shown);
  } catch (const Error&) {
    html << "<p id=\"model\">" << html_escape(shown_name) << " is not a valid binary glTF: " << model_link << "</p>\n";
    return html.str();
  }
  const Eigen::Matrix4d root = Eigen::Map<const Eigen::Matrix4d>(glb.root_matrix.data());
  std::vector<PhotoView> views;
  std::optional<RobustBounds> bounds = robust_bounds(surface_vertices(paths), root);
  if (bounds) {
    try {
      views = photo_views(read_colmap_model(paths.undistorted / "sparse"), root, *bounds);
    } catch (const Error&) {
      // No cameras: the viewer frames the model itself.
    }
  }
  if (meshopt) html << bundle_scripts(viewer_script, true);
  // The element may load its model before the viewer script below runs: a
  // capturing listener notes the load on it.
  html << "<script>document.addEventListener('load', (e) => { if (e.target.id === 'viewer') "
          "e.target.dataset.loaded = '1'; }, true);</script>\n";
  html << kViewerStyle << "\n<div id=\"viewer-frame\">\n<model-viewer id=\"viewer\" camera-controls "
       << "alt=\"the textured model\" ";
  if (!views.empty()) {
    const PhotoView& first = views.front();
    const double far = 20.0 * bounds->size + 2.0 * first.radius;
    // The photo's aspect, so its vertical field of view shows what it showed.
    html << "style=\"aspect-ratio: " << first.aspect << "\" camera-target=\"" << first.target.x() << "m "
         << first.target.y() << "m " << first.target.z() << "m\" camera-orbit=\"" << first.theta << "rad " << first.phi
         << "rad " << first.radius << "m\" field-of-view=\"" << first.vertical_fov_deg
         << "deg\" min-camera-orbit=\"auto auto 0m\" max-camera-orbit=\"auto auto " << far
         << "m\" min-field-of-view=\"1deg\" max-field-of-view=\"150deg\" ";
  } else {
    html << "style=\"aspect-ratio: 16 / 9\" ";
  }
  html << "src=\"data:model/gltf-binary;base64," << base64(shown_bytes) << "\">\n"
       << "</model-viewer>\n<svg id=\"viewer-frusta\"></svg>\n</div>\n";
  html << "<p>";
  if (!views.empty()) {
    html << "<label><input type=\"checkbox\" id=\"show-cameras\" checked> show the " << views.size()
         << " photos' cameras</label> (click one to see the model from it) · ";
  }
  if (preview) html << "shown: the preview " << html_escape(shown_name) << "; the full model: ";
  html << model_link << "</p>\n";
  if (!meshopt) html << bundle_scripts(viewer_script, false);
  if (!views.empty()) {
    html << "<script type=\"application/json\" id=\"viewer-data\">" << viewer_data_json(views, *bounds)
         << "</script>\n<script>" << kViewerScript << "</script>\n";
  }
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
