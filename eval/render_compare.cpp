#include "eval/render_compare.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

#include "core/error.h"
#include "eval/image_metrics.h"

namespace hos::eval {

RenderComparison compare_renders(const render::RenderObject& object,
                                 const SparseModel& model,
                                 const std::filesystem::path& images_dir,
                                 Reporter& reporter,
                                 const std::filesystem::path& save_dir) {
  RenderComparison out;
  if (!save_dir.empty()) std::filesystem::create_directories(save_dir);
  const std::vector<render::RenderObject> objects{object};
  render::RenderOptions options;
  options.lighting.unlit = true;  // the texture already holds the photographed shading
  reporter.begin("render", static_cast<std::int64_t>(model.images.size()));
  double sum_psnr = 0.0, sum_ssim = 0.0;
  std::size_t finite_psnr = 0;
  for (const auto& [id, image] : model.images) {
    reporter.throw_if_cancelled();
    const Camera& camera = model.camera_of(image);
    const std::filesystem::path photo_path = images_dir / image.name;
    const cv::Mat photo = cv::imread(photo_path.string(), cv::IMREAD_COLOR);
    if (photo.empty()) throw InputError(photo_path.string(), "missing or not a readable image");
    if (photo.cols != camera.width || photo.rows != camera.height) {
      throw InputError(photo_path.string(), "image size differs from its camera in the model");
    }
    const render::RenderedView view = render::render_view(objects, camera, image, options);
    reporter.advance();
    if (!save_dir.empty()) {
      cv::Mat render_with_mask, photo_opaque, side_by_side;
      cv::cvtColor(view.color, render_with_mask, cv::COLOR_BGR2BGRA);
      cv::insertChannel(view.mask, render_with_mask, 3);
      cv::cvtColor(photo, photo_opaque, cv::COLOR_BGR2BGRA);
      cv::hconcat(render_with_mask, photo_opaque, side_by_side);
      // Image names may hold folders ("DCIM/100APPLE/IMG_1.jpg"): kept, so
      // equal file names in two folders stay two files.
      const std::filesystem::path target = save_dir / std::filesystem::path(image.name).replace_extension(".png");
      std::filesystem::create_directories(target.parent_path());
      if (!cv::imwrite(target.string(), side_by_side)) throw OutputError(target.string(), "the image");
    }
    const std::size_t pixels = static_cast<std::size_t>(cv::countNonZero(view.mask));
    if (pixels == 0) {
      ++out.skipped_views;
      continue;
    }
    ViewComparison v;
    v.name = image.name;
    v.mask_pixels = pixels;
    v.psnr = masked_psnr(view.color, photo, view.mask);
    v.ssim = masked_ssim(view.color, photo, view.mask);
    if (std::isfinite(v.psnr)) {
      sum_psnr += v.psnr;
      ++finite_psnr;
    }
    sum_ssim += v.ssim;
    out.views.push_back(v);
  }
  reporter.end();
  if (out.views.empty()) throw StageError("eval", "the mesh is not visible from any camera of the model");
  out.mean_psnr =
      finite_psnr > 0 ? sum_psnr / static_cast<double>(finite_psnr) : std::numeric_limits<double>::infinity();
  out.mean_ssim = sum_ssim / static_cast<double>(out.views.size());
  return out;
}

SavedRender read_saved_render(const std::filesystem::path& path) {
  const cv::Mat image = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  if (image.empty()) throw InputError(path.string(), "missing or not a readable image");
  if (image.type() != CV_8UC4 || image.cols % 2 != 0) {
    throw InputError(path.string(), "not a render saved by hos-eval render --save (8-bit RGBA, render beside photo)");
  }
  const int width = image.cols / 2;
  SavedRender out;
  const cv::Mat render = image.colRange(0, width), photo = image.colRange(width, image.cols);
  cv::cvtColor(render, out.color, cv::COLOR_BGRA2BGR);
  cv::extractChannel(render, out.mask, 3);
  cv::cvtColor(photo, out.photo, cv::COLOR_BGRA2BGR);
  return out;
}

namespace {

// The saved views of one photo; throws InputError naming a view whose photo
// differs from the first's.
std::vector<SavedRender> read_runs(const std::vector<std::filesystem::path>& saved_views) {
  if (saved_views.empty()) throw std::invalid_argument("compare_on_common_pixels: no views");
  std::vector<SavedRender> runs;
  for (const auto& path : saved_views) {
    runs.push_back(read_saved_render(path));
    const SavedRender& first = runs.front();
    if (runs.back().photo.size() != first.photo.size() || cv::norm(runs.back().photo, first.photo, cv::NORM_INF) > 0) {
      throw InputError(path.string(),
                       "its photo differs from " + saved_views.front().string() + "'s: not a render of the same view");
    }
  }
  return runs;
}

std::string describe(const PixelRect& r) {
  return std::to_string(r.x) + "," + std::to_string(r.y) + "," + std::to_string(r.width) + "," +
         std::to_string(r.height);
}

cv::Rect to_cv(const PixelRect& r) { return {r.x, r.y, r.width, r.height}; }

// Each run's mean squared error over the common pixels of rect.
ErrorRegion region_error(const std::vector<SavedRender>& runs, const cv::Mat& common, const PixelRect& rect) {
  ErrorRegion region;
  region.rect = rect;
  const cv::Rect r = to_cv(rect);
  region.common_pixels = static_cast<std::size_t>(cv::countNonZero(common(r)));
  if (region.common_pixels == 0) return region;
  for (const SavedRender& run : runs) {
    const double norm = cv::norm(run.color(r), run.photo(r), cv::NORM_L2, common(r));
    region.mse.push_back(norm * norm / (3.0 * static_cast<double>(region.common_pixels)));
  }
  return region;
}

// Every tile holding common pixels, with each run's mean squared error there.
std::vector<ErrorRegion> tile_errors(const std::vector<SavedRender>& runs, const cv::Mat& common, int tile_size) {
  std::vector<ErrorRegion> tiles;
  const cv::Mat& photo = runs.front().photo;
  for (int y0 = 0; y0 < photo.rows; y0 += tile_size) {
    for (int x0 = 0; x0 < photo.cols; x0 += tile_size) {
      const PixelRect rect{x0, y0, std::min(tile_size, photo.cols - x0), std::min(tile_size, photo.rows - y0)};
      ErrorRegion tile = region_error(runs, common, rect);
      if (tile.common_pixels > 0) tiles.push_back(std::move(tile));
    }
  }
  return tiles;
}

double first_run_error(const ErrorRegion& r) {
  return r.mse.empty() ? 0.0 : r.mse.front() * static_cast<double>(r.common_pixels);
}

// The count tiles carrying most of the first run's squared error.
std::vector<ErrorRegion> worst_tiles(std::vector<ErrorRegion> tiles, std::size_t count) {
  std::stable_sort(tiles.begin(), tiles.end(),
                   [](const ErrorRegion& a, const ErrorRegion& b) { return first_run_error(a) > first_run_error(b); });
  tiles.resize(std::min(count, tiles.size()));
  return tiles;
}

// The options' regions, refusing one that does not lie inside the photo.
std::vector<ErrorRegion> region_errors(const std::vector<SavedRender>& runs,
                                       const cv::Mat& common,
                                       const std::vector<PixelRect>& rects) {
  const cv::Mat& photo = runs.front().photo;
  std::vector<ErrorRegion> regions;
  for (const PixelRect& r : rects) {
    if (r.width < 1 || r.height < 1 || r.x < 0 || r.y < 0 || r.x + r.width > photo.cols ||
        r.y + r.height > photo.rows) {
      throw ConfigError("region " + describe(r), "must lie inside the " + std::to_string(photo.cols) + "x" +
                                                     std::to_string(photo.rows) + " photo (X,Y,WIDTH,HEIGHT)");
    }
    regions.push_back(region_error(runs, common, r));
  }
  return regions;
}

void set_shares(std::vector<ErrorRegion>& regions, double total_error) {
  for (ErrorRegion& r : regions) r.share = total_error > 0.0 ? first_run_error(r) / total_error : 0.0;
}

// Writes the photo beside every run's render of rect to path, pixels a run
// does not cover in magenta.
void save_crop(const std::vector<SavedRender>& runs, const PixelRect& rect, const std::filesystem::path& path) {
  const cv::Rect r = to_cv(rect);
  std::vector<cv::Mat> parts{runs.front().photo(r).clone()};
  for (const SavedRender& run : runs) {
    cv::Mat part = run.color(r).clone();
    part.setTo(cv::Scalar(255, 0, 255), run.mask(r) == 0);
    parts.push_back(part);
  }
  cv::Mat side_by_side;
  cv::hconcat(parts, side_by_side);
  if (!cv::imwrite(path.string(), side_by_side)) throw OutputError(path.string(), "the image");
}

// dir/tile_X_Y.png for each tile, dir/region_X_Y_WxH.png for each region.
void save_crops(const std::vector<SavedRender>& runs, const CommonComparison& c, const std::filesystem::path& dir) {
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) throw OutputError(dir.string(), error.message());
  for (const ErrorRegion& t : c.worst_tiles) {
    save_crop(runs, t.rect, dir / ("tile_" + std::to_string(t.rect.x) + "_" + std::to_string(t.rect.y) + ".png"));
  }
  for (const ErrorRegion& r : c.regions) {
    save_crop(runs, r.rect,
              dir / ("region_" + std::to_string(r.rect.x) + "_" + std::to_string(r.rect.y) + "_" +
                     std::to_string(r.rect.width) + "x" + std::to_string(r.rect.height) + ".png"));
  }
}

}  // namespace

CommonComparison compare_on_common_pixels(const std::vector<std::filesystem::path>& saved_views,
                                          const CommonOptions& options) {
  if (options.tile_size < 1) throw std::invalid_argument("compare_on_common_pixels: tile_size < 1");
  const std::vector<SavedRender> runs = read_runs(saved_views);
  CommonComparison out;
  out.photo_pixels = runs.front().photo.total();
  cv::Mat common = runs.front().mask.clone();
  for (const SavedRender& run : runs) {
    out.covered_pixels.push_back(static_cast<std::size_t>(cv::countNonZero(run.mask)));
    cv::bitwise_and(common, run.mask, common);
  }
  out.common_pixels = static_cast<std::size_t>(cv::countNonZero(common));
  if (out.common_pixels == 0) throw InputError(saved_views.front().string(), "the runs cover no pixel in common");
  for (const SavedRender& run : runs) {
    out.psnr.push_back(masked_psnr(run.color, run.photo, common));
    out.ssim.push_back(masked_ssim(run.color, run.photo, common));
    out.psnr_exposure_matched.push_back(masked_psnr(exposure_matched(run.color, run.photo, common), run.photo, common));
  }
  if (!options.crops_dir.empty() && options.worst_tiles == 0 && options.regions.empty()) {
    throw ConfigError("crops " + options.crops_dir.string(), "needs worst tiles or regions to write");
  }
  if (options.worst_tiles > 0)
    out.worst_tiles = worst_tiles(tile_errors(runs, common, options.tile_size), options.worst_tiles);
  out.regions = region_errors(runs, common, options.regions);
  const double first_norm = cv::norm(runs.front().color, runs.front().photo, cv::NORM_L2, common);
  const double first_total_error = first_norm * first_norm / 3.0;
  set_shares(out.worst_tiles, first_total_error);
  set_shares(out.regions, first_total_error);
  if (!options.crops_dir.empty()) save_crops(runs, out, options.crops_dir);
  return out;
}

}  // namespace hos::eval
