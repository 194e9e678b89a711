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
bool depth_range(const SparseModel& model,
                 const ImageRecord& image,
                 std::vector<Eigen::Vector3d>& seeds,
                 double& dmin,
                 double& dmax) {
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

// What one reference view needs: its sources, depth range and seeds.
struct ViewPlan {
  const ImageRecord* image = nullptr;
  std::vector<int> sources;  // image ids
  std::vector<Eigen::Vector3d> seeds;
  double depth_min = 0, depth_max = 0;
  bool skipped = false;
};

std::vector<ViewPlan> plan_views(const SparseModel& model,
                                 const MvsOptions& options,
                                 Reporter& reporter,
                                 MvsStats& stats) {
  const auto sources = select_source_views(model, options);
  std::vector<ViewPlan> plans;
  for (const auto& [id, image] : model.images) {
    ViewPlan plan;
    plan.image = &image;
    plan.sources = sources[plans.size()];
    if (plan.sources.empty() || !depth_range(model, image, plan.seeds, plan.depth_min, plan.depth_max)) {
      reporter.warn(format_message("mvs: ", image.name,
                                   plan.sources.empty() ? ": no source view with enough overlap and baseline; skipped"
                                                        : ": too few sparse points to bound its depth; skipped"));
      plan.skipped = true;
      ++stats.views_skipped;
    }
    plans.push_back(std::move(plan));
  }
  return plans;
}

// Longest image sides of the matching levels, coarse to fine: the coarse
// size, then doubling up to the finest, which is at most the photos' size
// (one level when the coarse one is already that large).
std::vector<int> level_sizes(const MvsOptions& options, const SparseModel& model) {
  int photo_size = 0;
  for (const auto& [id, camera] : model.cameras) photo_size = std::max({photo_size, camera.width, camera.height});
  const int finest = std::min(options.max_image_size, photo_size);
  std::vector<int> sizes{std::min(options.coarse_image_size, finest)};
  while (sizes.back() < finest) sizes.push_back(std::min(2 * sizes.back(), finest));
  return sizes;
}

// A view and its sources at one size.
struct ViewSet {
  MvsView ref;
  std::vector<MvsView> sources;
  std::vector<const MvsView*> source_ptrs() const {
    std::vector<const MvsView*> out;
    for (const auto& s : sources) out.push_back(&s);
    return out;
  }
  ViewSet downscaled(int size) const {
    ViewSet out{downscale_view(ref, size), {}};
    for (const auto& s : sources) out.sources.push_back(downscale_view(s, size));
    return out;
  }
};

ViewSet load_view_set(const UndistortedWorkspace& workspace, const ViewPlan& plan, int size) {
  ViewSet set{load_view(workspace, *plan.image, size), {}};
  for (int id : plan.sources) set.sources.push_back(load_view(workspace, workspace.model.images.at(id), size));
  return set;
}

void write_depth_map(const std::filesystem::path& folder, const std::string& name, const DepthMap& map) {
  const std::string stem = (folder / name).string();
  std::filesystem::create_directories(std::filesystem::path(stem).parent_path());
  cv::imwrite(stem + ".depth.tiff", map.depth);
  cv::imwrite(stem + ".normal.tiff", map.normal);
}

}  // namespace

MvsResult run_mvs(const UndistortedWorkspace& workspace,
                  const MvsOptions& options,
                  Reporter& reporter,
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
  MvsResult result;
  MvsStats& stats = result.stats;
  const std::vector<ViewPlan> plans = plan_views(workspace.model, options, reporter, stats);
  stats.views = static_cast<int>(plans.size());
  const std::vector<int> sizes = level_sizes(options, workspace.model);
  if (!depth_map_folder.empty()) std::filesystem::create_directories(depth_map_folder);
  std::map<int, std::size_t> plan_of;
  for (std::size_t i = 0; i < plans.size(); ++i) plan_of[plans[i].image->id] = i;
  for (const auto& plan : plans) {
    MvsViewStats vs;
    vs.name = plan.image->name;
    vs.num_sources = static_cast<int>(plan.sources.size());
    vs.skipped = plan.skipped;
    stats.per_view.push_back(vs);
  }

  // Coarse level, every view: full PatchMatch. Its planes start the view's
  // finer levels; its reliable depths vote on the neighbours' finer levels.
  const bool multi_scale = sizes.size() > 1;
  const auto t_depth = Clock::now();
  std::vector<PlaneMap> coarse(plans.size());
  std::vector<DepthPrior> priors(plans.size());
  std::vector<FusionView> fusion_views;
  const auto finish_view = [&](std::size_t i, const MvsView& ref, const PlaneMap& planes, PatchMatchStats& pm) {
    DepthMap map = to_depth_map(planes, ref, options, &pm);
    MvsViewStats& vs = stats.per_view[i];
    vs.pixels = static_cast<std::size_t>(ref.width()) * static_cast<std::size_t>(ref.height());
    vs.valid_pixels = pm.valid_pixels;
    vs.textureless_pixels = pm.textureless_pixels;
    stats.megapixels_per_view = ref.width() * ref.height() / 1e6;
    if (!depth_map_folder.empty()) write_depth_map(depth_map_folder, plans[i].image->name, map);
    reporter.debug(format_message("mvs: ", vs.name, ": ", pm.valid_pixels, " pixels with depth, ",
                                  pm.textureless_pixels, " textureless, ", pm.refined_pixels, " refined, ",
                                  pm.restored_pixels, " restored against the coarse vote"));
    fusion_views.push_back(make_fusion_view(ref, std::move(map)));
  };
  reporter.begin("depth maps", static_cast<std::int64_t>(plans.size() * (multi_scale ? 2 : 1)));
  for (std::size_t i = 0; i < plans.size(); ++i) {
    reporter.throw_if_cancelled();
    if (plans[i].skipped) {
      reporter.advance();
      continue;
    }
    const auto t_view = Clock::now();
    const ViewSet views = load_view_set(workspace, plans[i], sizes.front());
    coarse[i] = match_planes(views.ref, views.source_ptrs(), plans[i].depth_min, plans[i].depth_max, plans[i].seeds,
                             options, reporter);
    if (multi_scale) {
      priors[i] = {views.ref.K, views.ref.R, views.ref.t, to_depth_map(coarse[i], views.ref, options).depth};
    } else {
      PatchMatchStats pm;
      finish_view(i, views.ref, coarse[i], pm);
    }
    stats.per_view[i].seconds += seconds_since(t_view);
    reporter.advance();
  }

  // Finer levels, one view at a time (only its images are in memory).
  for (std::size_t i = 0; multi_scale && i < plans.size(); ++i) {
    reporter.throw_if_cancelled();
    if (plans[i].skipped) {
      reporter.advance();
      continue;
    }
    const auto t_view = Clock::now();
    const ViewSet full = load_view_set(workspace, plans[i], sizes.back());
    std::vector<const DepthPrior*> source_priors;
    for (int id : plans[i].sources) source_priors.push_back(&priors[plan_of.at(id)]);
    PlaneMap planes = std::move(coarse[i]);
    PatchMatchStats pm;
    for (std::size_t level = 1; level < sizes.size(); ++level) {
      const bool finest = level + 1 == sizes.size();
      const ViewSet smaller = finest ? ViewSet{} : full.downscaled(sizes[level]);
      const ViewSet& views = finest ? full : smaller;
      planes = refine_planes(views.ref, views.source_ptrs(), source_priors, planes, plans[i].depth_min,
                             plans[i].depth_max, plans[i].seeds, options, reporter, &pm);
    }
    finish_view(i, full.ref, planes, pm);
    stats.per_view[i].seconds += seconds_since(t_view);
    reporter.advance();
  }
  reporter.end();
  stats.seconds_depth = seconds_since(t_depth);
  if (fusion_views.size() < 2) {
    throw StageError("mvs", "fewer than two views could be matched (" + std::to_string(fusion_views.size()) + " of " +
                                std::to_string(plans.size()) + "); the images overlap too little");
  }
  const auto t_fusion = Clock::now();
  // Density control is for the finer levels' pixels; one level keeps every pixel.
  MvsOptions fusion_options = options;
  if (!multi_scale) fusion_options.fusion_spacing_px = 0;
  result.points = fuse_depth_maps(fusion_views, fusion_options, reporter);
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
