#include "tests/mvs/synthetic_workspace.h"

#include <filesystem>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "core/ply_io.h"

namespace hos::mvs_testing {

SyntheticWorkspace make_synthetic_workspace(const synth::SceneOptions& scene_options,
                                            const synth::DatasetOptions& options) {
  SyntheticWorkspace s;
  s.dir = std::make_unique<hos::testing::TempDir>("hos-mvs-test");
  s.scene = synth::make_scene(scene_options);
  synth::write_dataset(s.dir->path() / "scene", s.scene, scene_options, options);
  s.truth = synth::render_dataset(s.scene, options);
  s.workspace = load_undistorted_workspace(s.dir->path() / "scene");
  s.diagonal = bounding_box(read_mesh_ply(s.dir->path() / "scene" / "gt_objects.ply").vertices).diagonal();
  return s;
}

UndistortedWorkspace edited_copy(const SyntheticWorkspace& s,
                                 const hos::testing::TempDir& dir,
                                 const std::function<void(cv::Mat&, std::size_t)>& edit) {
  std::filesystem::copy(s.dir->path() / "scene", dir.path() / "scene", std::filesystem::copy_options::recursive);
  std::size_t v = 0;
  for (const auto& [id, record] : s.truth.model.images) {
    const auto path = dir.path() / "scene" / "images" / record.name;
    cv::Mat image = cv::imread(path.string(), cv::IMREAD_COLOR);
    if (image.empty()) throw std::runtime_error("cannot read " + path.string());
    edit(image, v++);
    cv::imwrite(path.string(), image);
  }
  return load_undistorted_workspace(dir.path() / "scene");
}

const SyntheticWorkspace& synthetic_workspace() {
  static const SyntheticWorkspace instance = [] {
    synth::DatasetOptions options;
    options.num_views = 12;
    options.width = 320;
    options.height = 240;
    return make_synthetic_workspace(synth::SceneOptions{}, options);
  }();
  return instance;
}

TruthAtPoint truth_at(const SyntheticWorkspace& s, const Eigen::Vector3d& x) {
  TruthAtPoint best;
  std::size_t v = 0;
  for (const auto& [id, image] : s.truth.model.images) {
    const render::RenderedView& view = s.truth.views[v++];
    const Camera& camera = s.truth.model.camera_of(image);
    const Eigen::Vector3d xc = image.cam_from_world(x);
    const auto uv = camera.project(xc);
    if (!uv) continue;
    const int px = static_cast<int>(uv->x()), py = static_cast<int>(uv->y());
    if (px < 0 || py < 0 || px >= camera.width || py >= camera.height) continue;
    const float depth = view.depth.at<float>(py, px);
    if (!(depth > 0)) continue;
    const double along_ray = std::abs(xc.z() - depth) * xc.norm() / xc.z();
    if (along_ray < best.distance) {
      best.distance = along_ray;
      const cv::Vec3f n = view.normal.at<cv::Vec3f>(py, px);
      best.normal = Eigen::Vector3d(n[0], n[1], n[2]);
    }
  }
  return best;
}

std::optional<Eigen::Vector3d> surface_point(const SyntheticWorkspace& s, std::size_t v, int x, int y) {
  const float d = s.truth.views[v].depth.at<float>(y, x);
  if (!(d > 0)) return std::nullopt;
  auto image = s.truth.model.images.begin();
  std::advance(image, static_cast<std::ptrdiff_t>(v));
  const Camera& camera = s.truth.model.camera_of(image->second);
  return image->second.world_from_cam(camera.unproject({x + 0.5, y + 0.5}) * d);
}

}  // namespace hos::mvs_testing
