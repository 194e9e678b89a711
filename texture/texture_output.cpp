#include "texture/texture_output.h"

#include <algorithm>

#include "texture/decimate.h"
#include "texture/gltf_writer.h"
#include "texture/model_writer.h"
#include "texture/up_direction.h"

namespace hos::texture {
namespace {

constexpr int kPreviewJpegQuality = 85;
// The preview is for web viewers (model-viewer, three.js), which read both
// extensions: its geometry is 16-bit and meshopt-compressed whatever the
// model's mesh_compression (32-bit floats made a 150000-face preview of a
// model with many small charts 9 MB of geometry).
constexpr const char* kPreviewMeshCompression = "meshopt";

}  // namespace

void write_texture_outputs(const std::filesystem::path& output,
                           const TextureResult& result,
                           const TextureOptions& options,
                           Reporter& reporter) {
  GltfWriteOptions write_options;
  write_options.image_format = options.image_format;
  write_options.jpeg_quality = options.jpeg_quality;
  write_options.mesh_compression = options.mesh_compression;
  write_model(output, result.mesh, write_options);
  if (options.preview_max_faces <= 0) return;
  DecimationStats preview_stats;
  const TexturedMesh preview = preview_model(result.mesh, static_cast<std::size_t>(options.preview_max_faces),
                                             options.preview_atlas_size, &preview_stats);
  const std::filesystem::path preview_path = preview_model_path(output);
  // A web page's budget, whatever the model's options: a JPEG atlas of
  // quality at most kPreviewJpegQuality, compressed geometry.
  GltfWriteOptions preview_options = write_options;
  preview_options.image_format = "jpeg";
  preview_options.jpeg_quality = std::min(write_options.jpeg_quality, kPreviewJpegQuality);
  preview_options.mesh_compression = kPreviewMeshCompression;
  write_glb(preview_path, preview, preview_options);
  reporter.info(format_message("wrote the preview ", preview_path.string(), " (", preview_stats.faces_after,
                               " faces, atlas ", preview.atlases[0].cols, "x", preview.atlases[0].rows, ")"));
}

void log_texture_summary(const TextureResult& result, Reporter& reporter) {
  const TextureStats& s = result.stats;
  reporter.info(format_message("textured ", s.faces, " faces from ", s.num_views, " photos: ", s.num_charts,
                               " charts in ", s.num_atlases, " atlas(es) (", s.atlas_coverage,
                               " of the texels in triangles), ", s.num_unseen_faces, " unseen faces, ",
                               s.num_outlier_rejections, " outlier views rejected"));
  const auto& placed = result.placement;
  reporter.info(format_message("up from ", up_method_name(placed.up.method),
                               placed.up.fallback_reason.empty() ? "" : " (" + placed.up.fallback_reason + ")", "; ",
                               placed.units_text()));
  reporter.info(
      format_message("seam colour jump ", s.mean_seam_jump_before, " -> ", s.mean_seam_jump_after, " (8-bit RGB)"));
  for (const auto& [step, seconds] : s.step_seconds) reporter.debug(format_message("step ", step, ": ", seconds, " s"));
}

}  // namespace hos::texture
