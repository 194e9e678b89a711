#include "mvs/run_mvs.h"

#include <algorithm>
#include <chrono>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "mvs/fusion.h"
#include "mvs/patch_match.h"
#include "mvs/view_selection.h"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace hos::mvs {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Depth range of a view from the sparse points in front of it (2nd-98th
// percentile, widened), so PatchMatch samples where the scene is.
bool depth_range(const SparseModel& model, const ImageRecord& image, std::vector<Eigen::Vector3d>& seeds,
                 double& dmin, double& dmax) {
  std::vector<double> depths;
  const Camera& camera = model.camera_of(image);
  for (const auto& [id, point] : model.points) {
    const Eigen::Vector3d xc = image.cam_from_world(point.xyz);
    if (xc.z() <= 0) continue;
    const auto uv = camera.project(xc);
    if (!uv || uv->x() < 0 || uv->y() < 0 || uv->x() >= camera.width || uv->y() >= camera.height) continue;
    depths.push_back(xc.z());
    // Only points the image observes seed it (others may be occluded).
    for (const auto& e : point.track) {
      if (e.image_id == image.id) {
        seeds.push_back(point.xyz);
        break;
      }
    }
  }
  if (depths.size() < 3) return false;
  std::sort(depths.begin(), depths.end());
  dmin = depths[depths.size() * 2 / 100] * 0.7;
  dmax = depths[std::min(depths.size() - 1, depths.size() * 98 / 100)] * 1.4;
  return dmax > dmin && dmin > 0;
}

}  // namespace

MvsResult run_mvs(const UndistortedWorkspace& workspace, const MvsOptions& options, Reporter& reporter,
                  const std::filesystem::path& depth_map_folder) {
  options.validate();
  if (options.backend == "colmap") {
    throw ConfigError("mvs.backend",
                      "the colmap backend needs COLMAP built with CUDA, which this installation is not; "
                      "use mvs.backend=cpu");
  }
#ifdef _OPENMP
  if (options.threads > 0) omp_set_num_threads(options.threads);
#endif
  const SparseModel& model = workspace.model;
  const auto sources = select_source_views(model, options);
  std::vector<const ImageRecord*> images;
  for (const auto& [id, image] : model.images) images.push_back(&image);
  std::map<int, std::size_t> index_of;
  for (std::size_t i = 0; i < images.size(); ++i) index_of[images[i]->id] = i;

  MvsResult result;
  MvsStats& stats = result.stats;
  stats.views = static_cast<int>(images.size());
  std::vector<FusionView> fusion_views;
  if (!depth_map_folder.empty()) std::filesystem::create_directories(depth_map_folder);

  const auto t_depth = Clock::now();
  reporter.begin("depth maps", static_cast<std::int64_t>(images.size()));
  for (std::size_t i = 0; i < images.size(); ++i) {
    reporter.throw_if_cancelled();
    const ImageRecord& image = *images[i];
    MvsViewStats vs;
    vs.name = image.name;
    vs.num_sources = static_cast<int>(sources[i].size());
    std::vector<Eigen::Vector3d> seeds;
    double dmin = 0, dmax = 0;
    const auto t_view = Clock::now();
    if (sources[i].empty() || !depth_range(model, image, seeds, dmin, dmax)) {
      reporter.warn(format_message("mvs: ", image.name,
                                   sources[i].empty() ? ": no source view with enough overlap and baseline; skipped"
                                                      : ": too few sparse points to bound its depth; skipped"));
      vs.skipped = true;
      ++stats.views_skipped;
      stats.per_view.push_back(vs);
      reporter.advance();
      continue;
    }
    // Only the images this reference view needs are in memory.
    const MvsView ref = load_view(workspace, image, options.max_image_size);
    std::vector<MvsView> source_views;
    for (int id : sources[i]) source_views.push_back(load_view(workspace, model.images.at(id), options.max_image_size));
    std::vector<const MvsView*> source_ptrs;
    for (const auto& s : source_views) source_ptrs.push_back(&s);
    PatchMatchStats pm;
    DepthMap map = estimate_depth_map(ref, source_ptrs, dmin, dmax, seeds, options, reporter, &pm);
    vs.valid_pixels = pm.valid_pixels;
    vs.textureless_pixels = pm.textureless_pixels;
    vs.seconds = seconds_since(t_view);
    stats.megapixels_per_view = ref.width() * ref.height() / 1e6;
    if (!depth_map_folder.empty()) {
      const std::string stem = (depth_map_folder / image.name).string();
      std::filesystem::create_directories(std::filesystem::path(stem).parent_path());
      cv::imwrite(stem + ".depth.tiff", map.depth);
      cv::imwrite(stem + ".normal.tiff", map.normal);
    }
    reporter.debug(format_message("mvs: ", image.name, ": ", pm.valid_pixels, " pixels with depth, ",
                                  pm.textureless_pixels, " textureless, ", vs.seconds, " s"));
    fusion_views.push_back(make_fusion_view(ref, std::move(map)));
    stats.per_view.push_back(vs);
    reporter.advance();
  }
  reporter.end();
  stats.seconds_depth = seconds_since(t_depth);
  if (fusion_views.size() < 2) {
    throw StageError("mvs", "fewer than two views could be matched (" + std::to_string(fusion_views.size()) +
                                " of " + std::to_string(images.size()) + "); the images overlap too little");
  }
  const auto t_fusion = Clock::now();
  result.points = fuse_depth_maps(fusion_views, options, reporter);
  stats.seconds_fusion = seconds_since(t_fusion);
  stats.points = result.points.size();
  if (result.points.empty()) {
    throw StageError("mvs", "no point is consistent across views (textureless or non-overlapping images)");
  }
  reporter.info(format_message("mvs: ", stats.points, " points from ", stats.views - stats.views_skipped, "/",
                               stats.views, " views; depth maps ", stats.seconds_depth, " s, fusion ",
                               stats.seconds_fusion, " s"));
  return result;
}

}  // namespace hos::mvs
