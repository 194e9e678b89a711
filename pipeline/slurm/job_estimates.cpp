#include "pipeline/slurm/job_estimates.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>

#include "mvs/fusion_store.h"
#include "mvs/mvs_options.h"
#include "mvs/patch_match.h"
#include "recon/recon_options.h"
#include "refine/refine_options.h"
#include "sfm/sfm_options.h"
#include "texture/texture_options.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

// Measured speeds, CPU seconds (user + sys), each the largest of its table:
// sfm per photo: fountain-P11, 88 CPU s for 11 photos of 6.3 MP
// (docs/benchmarks-sfm.md, 2ce2897).
constexpr double kSfmCpuSecondsPerPhoto = 8.0;
// mvs per view per matched MP: fountain-P11 matched in one level at 1024 px,
// 185 CPU s for 10 views of 0.70 MP (docs/benchmarks-mvs.md); the whole run,
// fusion included.
constexpr double kMvsCpuSecondsPerViewMp = 26.5;
// recon at grid 1024: the bunny, 41.3 CPU s (docs/benchmarks-recon.md, b352fee);
// the work grows with the grid's nodes.
constexpr double kReconCpuSecondsAtGrid1024 = 41.3;
// refine per view per photo MP at its default face budget: Herz-Jesu-P8,
// 42.9 CPU s for 8 photos of 6.3 MP, 300000 faces (docs/refine.md, bccbf03).
constexpr double kRefineCpuSecondsPerViewMp = 0.85;
constexpr double kRefineMeasuredFaces = 300000.0;
// texture (docs/benchmarks-texture.md, e6afa7c, 1 M faces, 50 views of
// 1.23 MP, 2 cores): visibility 18.83 s wall, at most 0.75 CPU s per view;
// each of the photo's pixels and the faces is taken to cost all of it
// alone, an upper bound. The rest, 43.7 s wall, at most 1.75e-6 CPU s per
// face and view.
constexpr double kTextureVisibilityCpuSecondsPerView = 0.75;
constexpr double kTextureMeasuredMp = 1.23;
constexpr double kTextureMeasuredFaces = 1e6;
constexpr double kTextureAtlasCpuSecondsPerFaceView = 1.75e-6;

// Megapixels of a 4:3 image whose longest side is size.
double megapixels_at(int size) { return 0.75 * double(size) * size / 1e6; }

// The faces texture works on: its decimation bound, else refine's face
// budget; 0 when neither bounds them (refine off, no decimation).
double texture_faces(const PipelineConfig& config) {
  const auto* texture = stage_options<texture::TextureOptions>(config, "texture");
  if (texture && texture->max_faces > 0) return texture->max_faces;
  const auto* refine = stage_options<refine::RefineOptions>(config, "refine");
  return refine && refine->enabled ? refine->max_faces : 0.0;
}

// recon as one job, or a tiled recon's tile tasks and join.
bool is_recon_job(const std::string& job) { return job == "recon" || job == "recon-tiles" || job == "recon-join"; }

}  // namespace

RunBounds run_bounds(const fs::path& photos, const PipelineConfig& config) {
  RunBounds bounds;
  int files = 0;
  std::uintmax_t largest_size = 0;
  fs::path largest;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(photos, ec)) {
    if (!entry.is_regular_file(ec) || entry.path().filename().string().rfind('.', 0) == 0) continue;
    ++files;
    const std::uintmax_t size = entry.file_size(ec);
    if (!ec && size > largest_size) {
      largest_size = size;
      largest = entry.path();
    }
  }
  bounds.views = std::max(files, 1);
  if (!largest.empty()) {
    // Decoded at 1/8 (JPEG decodes only the DCT's low frequencies); each
    // pixel stands for up to 8x8 of the photo.
    const cv::Mat reduced = cv::imread(largest.string(), cv::IMREAD_REDUCED_GRAYSCALE_8);
    if (!reduced.empty()) bounds.photo_megapixels = 64.0 * reduced.total() / 1e6;
  }
  const auto* sfm = stage_options<sfm::SfmOptions>(config, "sfm");
  if (sfm && sfm->max_image_size > 0) {
    const double cap = megapixels_at(sfm->max_image_size);
    bounds.photo_megapixels = bounds.photo_megapixels > 0 ? std::min(bounds.photo_megapixels, cap) : cap;
  }
  return bounds;
}

int job_memory_mb(const std::string& job, const PipelineConfig& config, int views, int default_mb) {
  if (job == "mvs-depth" || job == "mvs-fuse") {
    if (const auto* mvs = stage_options<mvs::MvsOptions>(config, "mvs")) {
      // The finest level at a 4:3 aspect; a depth chunk holds the reference
      // view and its sources (grey float + colour), the planes, costs and
      // the sources' coarse priors; fusion what its store holds at most.
      const double pixels = 0.75 * double(mvs->max_image_size) * mvs->max_image_size;
      const double bytes = job == "mvs-depth"
                               ? pixels * (7.0 * (1 + mvs->num_source_views) + mvs::matcher_bytes_per_pixel(*mvs))
                               : mvs::fusion_peak_bytes(*mvs, pixels, views);
      return static_cast<int>(std::ceil(512.0 + 1.5 * bytes / (1024.0 * 1024.0)));
    }
  }
  if (is_recon_job(job)) {
    // recon refuses a grid whose estimated peak exceeds its budget, so the
    // budget (with room for the process itself) bounds the job. The tiles'
    // count is known before the points, their sizes are not: the budget
    // bounds each tile task too (hos-recon --tile refuses a tile whose
    // solve's estimate exceeds it), and the join, which holds one core at a
    // time, asks for the same.
    const auto* recon = stage_options<recon::ReconOptions>(config, "recon");
    if (recon && recon->max_memory_mb > 0) return recon->max_memory_mb + 512;
  }
  return default_mb;
}

double job_cpu_seconds(const std::string& job, const PipelineConfig& config, const RunBounds& bounds, int chunk_views) {
  const double views = std::max(bounds.views, 1);
  const double chunk = std::clamp(double(chunk_views), 1.0, views);
  if (job == "sfm") return views * kSfmCpuSecondsPerPhoto;
  if (job == "mvs-depth" || job == "mvs-fuse") {
    const auto* mvs = stage_options<mvs::MvsOptions>(config, "mvs");
    if (!mvs) return 0;
    double fine_mp = megapixels_at(mvs->max_image_size);
    if (bounds.photo_megapixels > 0) fine_mp = std::min(fine_mp, bounds.photo_megapixels);
    if (job == "mvs-fuse") return views * fine_mp * kMvsCpuSecondsPerViewMp;  // bounded by the whole run
    // With finer levels a chunk also matches its sources' coarse level:
    // up to num_source_views more coarse views per view, at most every view.
    const bool multi_scale = mvs->max_image_size > mvs->coarse_image_size;
    const double coarse_views = multi_scale ? std::min(views - chunk, chunk * mvs->num_source_views) : 0.0;
    const double coarse_mp = std::min(fine_mp, megapixels_at(mvs->coarse_image_size));
    return (chunk * fine_mp + coarse_views * coarse_mp) * kMvsCpuSecondsPerViewMp;
  }
  if (is_recon_job(job)) {
    // A tile's grid is cut at the samples' median, not at an even share of
    // the nodes, so it may span most of the whole grid: the whole grid's
    // time bounds each tile, and the join (blending and meshing, no solve).
    const auto* recon = stage_options<recon::ReconOptions>(config, "recon");
    if (!recon || recon->resolution <= 0) return 0;  // the grid follows the points' density: unknown before
    return kReconCpuSecondsAtGrid1024 * std::pow(recon->resolution / 1024.0, 3);
  }
  if (bounds.photo_megapixels <= 0) return 0;
  if (job == "refine") {
    const auto* refine = stage_options<refine::RefineOptions>(config, "refine");
    if (!refine || !refine->enabled) return 0;
    const double faces_factor = std::max(1.0, refine->max_faces / kRefineMeasuredFaces);
    return views * bounds.photo_megapixels * kRefineCpuSecondsPerViewMp * faces_factor;
  }
  const double faces = texture_faces(config);
  if (faces <= 0) return 0;
  if (job == "texture-views") {
    return chunk * kTextureVisibilityCpuSecondsPerView *
           (bounds.photo_megapixels / kTextureMeasuredMp + faces / kTextureMeasuredFaces);
  }
  if (job == "texture-atlas") return faces * views * kTextureAtlasCpuSecondsPerFaceView;
  return 0;
}

std::string job_time_limit(const std::string& job,
                           const PipelineConfig& config,
                           const RunBounds& bounds,
                           int chunk_views,
                           const std::string& time_option) {
  if (!time_option.empty()) return time_option;
  const double seconds = job_cpu_seconds(job, config, bounds, chunk_views);
  if (seconds <= 0) return "";
  return slurm_time_text(std::max(kMinTimeSeconds, kTimeSafetyFactor * seconds));
}

std::string slurm_time_text(double seconds) {
  const long minutes = static_cast<long>(std::ceil(std::max(seconds, 0.0) / 60.0));
  const long days = minutes / (24 * 60), hours = minutes / 60 % 24, rest = minutes % 60;
  char text[48];
  if (days > 0) {
    std::snprintf(text, sizeof(text), "%ld-%02ld:%02ld:00", days, hours, rest);
  } else {
    std::snprintf(text, sizeof(text), "%02ld:%02ld:00", hours, rest);
  }
  return text;
}

}  // namespace hos::pipeline
