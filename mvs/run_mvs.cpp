#include "mvs/run_mvs.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <opencv2/imgcodecs.hpp>
#include <set>

#include "core/error.h"
#include "core/stopwatch.h"
#include "mvs/depth_map_file.h"
#include "mvs/fusion.h"
#include "mvs/fusion_store.h"
#include "mvs/patch_match.h"
#include "mvs/view_selection.h"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace hos::mvs {
namespace {

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
  std::vector<int> sources;            // image ids
  std::vector<int> fusion_neighbours;  // image ids fusion checks its depths against
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
  std::set<int> skipped;
  for (const auto& [id, image] : model.images) {
    ViewPlan plan;
    plan.image = &image;
    plan.sources = sources[plans.size()];
    if (plan.sources.empty() || !depth_range(model, image, plan.seeds, plan.depth_min, plan.depth_max)) {
      reporter.warn(format_message("mvs: ", image.name,
                                   plan.sources.empty() ? ": no source view with enough overlap and baseline; skipped"
                                                        : ": too few sparse points to bound its depth; skipped"));
      plan.skipped = true;
      skipped.insert(id);
      ++stats.views_skipped;
    }
    plans.push_back(std::move(plan));
  }
  // Fusion's neighbours among the views that will have depth maps.
  const auto fusion_neighbours = select_fusion_views(model, options.fusion_max_views, skipped);
  for (std::size_t i = 0; i < plans.size(); ++i) plans[i].fusion_neighbours = fusion_neighbours[i];
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

// A view's maps in folder: TIFFs to look at, the .dmap file to fuse again.
void write_depth_map(const std::filesystem::path& folder, const std::string& name, const DepthMap& map) {
  const std::string stem = (folder / name).string();
  std::filesystem::create_directories(std::filesystem::path(stem).parent_path());
  cv::imwrite(stem + ".depth.tiff", map.depth);
  cv::imwrite(stem + ".normal.tiff", map.normal);
  write_depth_map_file(depth_map_file(folder, name), map);
}

// The view's map from folder, which must be of the view's matching size.
DepthMap read_view_depth_map(const std::filesystem::path& folder, const MvsView& view, const std::string& name) {
  const std::filesystem::path file = depth_map_file(folder, name);
  DepthMap map = read_depth_map_file(file);
  if (map.depth.cols != view.width() || map.depth.rows != view.height()) {
    throw InputError(file.string(), "depth map of " + std::to_string(map.depth.cols) + "x" +
                                        std::to_string(map.depth.rows) + " pixels, the view is " +
                                        std::to_string(view.width()) + "x" + std::to_string(view.height()) +
                                        " (computed with other options?)");
  }
  return map;
}

// What every mode shares: the views' plans and the matching levels.
struct MvsPlan {
  std::vector<ViewPlan> views;
  std::vector<int> sizes;
  std::map<int, std::size_t> index_of;  // image id -> index into views
  bool multi_scale() const { return sizes.size() > 1; }
};

MvsPlan make_plan(const UndistortedWorkspace& workspace,
                  const MvsOptions& options,
                  Reporter& reporter,
                  MvsStats& stats) {
  options.validate();
  if (options.backend == "colmap") {
    throw ConfigError("mvs.backend",
                      "the colmap backend needs COLMAP built with CUDA, which this installation is not; "
                      "use mvs.backend=cpu");
  }
#ifdef _OPENMP
  if (options.threads > 0) omp_set_num_threads(options.threads);
#endif
  MvsPlan plan;
  plan.views = plan_views(workspace.model, options, reporter, stats);
  plan.sizes = level_sizes(options, workspace.model);
  for (std::size_t i = 0; i < plan.views.size(); ++i) plan.index_of[plan.views[i].image->id] = i;
  stats.views = static_cast<int>(plan.views.size());
  for (const auto& view : plan.views) {
    MvsViewStats vs;
    vs.name = view.image->name;
    vs.num_sources = static_cast<int>(view.sources.size());
    vs.skipped = view.skipped;
    stats.per_view.push_back(vs);
  }
  return plan;
}

using DepthMapSink = std::function<void(std::size_t view, const MvsView& ref, DepthMap map)>;

// The depth maps of the selected views, each handed to sink in view order.
// Coarse level, every selected view and (with finer levels) its sources:
// full PatchMatch. Its planes start the view's finer levels; its reliable
// depths vote on the neighbours' finer levels.
void match_views(const UndistortedWorkspace& workspace,
                 const MvsOptions& options,
                 const MvsPlan& plan,
                 const std::vector<bool>& selected,
                 Reporter& reporter,
                 MvsStats& stats,
                 const DepthMapSink& sink) {
  const auto& plans = plan.views;
  const auto& sizes = plan.sizes;
  const bool multi_scale = plan.multi_scale();
  std::vector<bool> coarse_needed = selected;
  for (std::size_t i = 0; multi_scale && i < plans.size(); ++i) {
    if (!selected[i] || plans[i].skipped) continue;
    for (int id : plans[i].sources) coarse_needed[plan.index_of.at(id)] = true;
  }
  const auto t_depth = Clock::now();
  std::vector<PlaneMap> coarse(plans.size());
  std::vector<DepthPrior> priors(plans.size());
  const auto finish_view = [&](std::size_t i, const MvsView& ref, const PlaneMap& planes, PatchMatchStats& pm) {
    DepthMap map = to_depth_map(planes, ref, options, &pm);
    MvsViewStats& vs = stats.per_view[i];
    vs.pixels = static_cast<std::size_t>(ref.width()) * static_cast<std::size_t>(ref.height());
    vs.valid_pixels = pm.valid_pixels;
    vs.textureless_pixels = pm.textureless_pixels;
    stats.megapixels_per_view = ref.width() * ref.height() / 1e6;
    reporter.debug(format_message("mvs: ", vs.name, ": ", pm.valid_pixels, " pixels with depth, ",
                                  pm.textureless_pixels, " textureless, ", pm.refined_pixels, " refined, ",
                                  pm.restored_pixels, " restored against the coarse vote"));
    sink(i, ref, std::move(map));
  };
  const auto work = std::count(coarse_needed.begin(), coarse_needed.end(), true) +
                    (multi_scale ? std::count(selected.begin(), selected.end(), true) : 0);
  reporter.begin("depth maps", static_cast<std::int64_t>(work));
  for (std::size_t i = 0; i < plans.size(); ++i) {
    if (!coarse_needed[i]) continue;
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
    if (!selected[i]) continue;
    reporter.throw_if_cancelled();
    if (plans[i].skipped) {
      reporter.advance();
      continue;
    }
    const auto t_view = Clock::now();
    const ViewSet full = load_view_set(workspace, plans[i], sizes.back());
    std::vector<const DepthPrior*> source_priors;
    for (int id : plans[i].sources) source_priors.push_back(&priors[plan.index_of.at(id)]);
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
}

// Fusion's views, in view order, with the plan index of each.
struct FusionInput {
  FusionViewStore store;
  std::vector<std::size_t> plan_index;
  FusionInput(const MvsOptions& options, const UndistortedWorkspace& workspace, const MvsPlan& plan)
      : store(static_cast<std::size_t>(options.fusion_memory_mb) << 20U) {
    // Maps that will not all fit spill: a spill folder that cannot be made
    // is named now rather than after the depth maps.
    if (options.fusion_memory_mb > 0 &&
        finest_map_bytes(workspace, plan) > double(options.fusion_memory_mb) * (1 << 20)) {
      store.make_spill_folder();
    }
  }
  // The store's bytes for every matched view's finest maps.
  static double finest_map_bytes(const UndistortedWorkspace& workspace, const MvsPlan& plan) {
    double pixels = 0;
    for (const ViewPlan& view : plan.views) {
      if (view.skipped) continue;
      const Camera& camera = workspace.model.camera_of(*view.image);
      const double scale = std::min(1.0, double(plan.sizes.back()) / std::max(camera.width, camera.height));
      pixels += std::round(camera.width * scale) * std::round(camera.height * scale);
    }
    return pixels * fusion_bytes_per_pixel();
  }
  void add(std::size_t view, const MvsView& ref, const DepthMap& map) {
    store.add(make_fusion_view(ref, map));
    plan_index.push_back(view);
  }
};

// Each fused view's neighbours as indices into the store (which holds the
// maps of every view not skipped, and no skipped view is a neighbour).
std::vector<std::vector<std::size_t>> fusion_neighbours(const FusionInput& input, const MvsPlan& plan) {
  std::map<std::size_t, std::size_t> store_index;  // plan index -> store index
  for (std::size_t i = 0; i < input.plan_index.size(); ++i) store_index[input.plan_index[i]] = i;
  std::vector<std::vector<std::size_t>> neighbours;
  for (std::size_t view : input.plan_index) {
    std::vector<std::size_t> indices;
    for (int id : plan.views[view].fusion_neighbours) indices.push_back(store_index.at(plan.index_of.at(id)));
    neighbours.push_back(std::move(indices));
  }
  return neighbours;
}

// Fusion of the matched views (in view order) into the result's points.
void fuse_views(
    FusionInput& input, const MvsPlan& plan, const MvsOptions& options, Reporter& reporter, MvsResult& result) {
  MvsStats& stats = result.stats;
  if (input.store.size() < 2) {
    throw StageError("mvs", "fewer than two views could be matched (" + std::to_string(input.store.size()) + " of " +
                                std::to_string(plan.views.size()) + "); the images overlap too little");
  }
  const auto t_fusion = Clock::now();
  // Density control is for the finer levels' pixels; one level keeps every pixel.
  MvsOptions fusion_options = options;
  if (!plan.multi_scale()) fusion_options.fusion_spacing_px = 0;
  result.points = fuse_depth_maps(input.store, fusion_neighbours(input, plan), fusion_options, reporter);
  stats.seconds_fusion = seconds_since(t_fusion);
  stats.points = result.points.size();
  if (result.points.empty()) {
    throw StageError("mvs", "no point is consistent across views (textureless or non-overlapping images)");
  }
  reporter.debug(format_message("mvs: fusion held at most ", input.store.peak_resident_bytes() >> 20U, " MB of maps; ",
                                input.store.spilled_views(), " views spilled, ", input.store.maps_read_back(),
                                " read back"));
  reporter.info(format_message("mvs: ", stats.points, " points from ", stats.views - stats.views_skipped, "/",
                               stats.views, " views; depth maps ", stats.seconds_depth, " s, fusion ",
                               stats.seconds_fusion, " s"));
}

}  // namespace

MvsResult run_mvs(const UndistortedWorkspace& workspace,
                  const MvsOptions& options,
                  Reporter& reporter,
                  const std::filesystem::path& depth_map_folder) {
  MvsResult result;
  const MvsPlan plan = make_plan(workspace, options, reporter, result.stats);
  if (!depth_map_folder.empty()) std::filesystem::create_directories(depth_map_folder);
  FusionInput fusion(options, workspace, plan);
  match_views(workspace, options, plan, std::vector<bool>(plan.views.size(), true), reporter, result.stats,
              [&](std::size_t i, const MvsView& ref, const DepthMap& map) {
                if (!depth_map_folder.empty()) write_depth_map(depth_map_folder, plan.views[i].image->name, map);
                fusion.add(i, ref, map);
              });
  fuse_views(fusion, plan, options, reporter, result);
  return result;
}

int count_views(const UndistortedWorkspace& workspace) { return static_cast<int>(workspace.model.images.size()); }

MvsStats compute_depth_maps(const UndistortedWorkspace& workspace,
                            const MvsOptions& options,
                            Reporter& reporter,
                            const ViewRange& range,
                            const std::filesystem::path& folder) {
  MvsStats stats;
  const MvsPlan plan = make_plan(workspace, options, reporter, stats);
  const std::vector<bool> selected = range.selection(static_cast<int>(plan.views.size()));
  std::filesystem::create_directories(folder);
  match_views(workspace, options, plan, selected, reporter, stats,
              [&](std::size_t i, const MvsView&, const DepthMap& map) {
                write_depth_map(folder, plan.views[i].image->name, map);
              });
  const auto count = std::count(selected.begin(), selected.end(), true);
  reporter.info(format_message("mvs: depth maps of views ", range.first, "-", range.last, ": ", count, " of ",
                               plan.views.size(), " views in ", stats.seconds_depth, " s"));
  return stats;
}

MvsResult fuse_depth_map_folder(const UndistortedWorkspace& workspace,
                                const MvsOptions& options,
                                Reporter& reporter,
                                const std::filesystem::path& folder) {
  MvsResult result;
  const MvsPlan plan = make_plan(workspace, options, reporter, result.stats);
  FusionInput fusion(options, workspace, plan);
  reporter.begin("reading depth maps", static_cast<std::int64_t>(plan.views.size()));
  for (std::size_t i = 0; i < plan.views.size(); ++i) {
    const ViewPlan& view = plan.views[i];
    reporter.throw_if_cancelled();
    reporter.advance();
    if (view.skipped) continue;
    const MvsView ref = load_view(workspace, *view.image, plan.sizes.back());
    fusion.add(i, ref, read_view_depth_map(folder, ref, view.image->name));
  }
  reporter.end();
  fuse_views(fusion, plan, options, reporter, result);
  return result;
}

}  // namespace hos::mvs
