// The per-view results of split texture runs (docs/texture.md, "Split
// runs"): one file per view holding what compute_view_visibility found, so
// parts over ranges of views can run as separate processes and one run
// joins them. A file read back is the samples written, bit for bit.
//
// Layout (native byte order, as the machine that wrote it; clusters share one):
//   char[8]  tag "HOSTVIEW"
//   uint32   format version (kViewDataVersion)
//   int32    view index (0-based, in the model's image id order)
//   int32    faces of the mesh the samples refer to (after decimation)
//   uint64   fingerprint of the mesh, the view's camera and pose and the
//            visibility options (view_data_fingerprint)
//   uint64   number of samples n
//   n times: int32 face, float32 gradient_integral, visible_px,
//            projected_area_px, cos_angle, mean_rgb[3]
// and nothing after.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "core/types.h"
#include "texture/texture_options.h"
#include "texture/texture_view.h"
#include "texture/visibility.h"

namespace hos::texture {

inline constexpr std::uint32_t kViewDataVersion = 1;

// What a view's file must match to be used: its view, the mesh's face count
// and the fingerprint of everything its samples depend on except the pixels.
struct ViewDataKey {
  int view_index = 0;
  int num_faces = 0;
  std::uint64_t fingerprint = 0;
};

// folder/<image name>.tvis.
std::filesystem::path view_data_file(const std::filesystem::path& folder, const std::string& view_name);

// FNV-1a over the mesh's vertices and faces, the view's camera and pose and
// the options the visibility test reads: files from another mesh, model or
// options are refused.
std::uint64_t view_data_fingerprint(const TriangleMesh& mesh, const TextureView& view, const TextureOptions& options);

// Writes the samples atomically (creating the folder). Throws OutputError.
void write_view_data(const std::filesystem::path& file, const ViewDataKey& key, const ViewSamples& samples);

// Reads a file write_view_data wrote for key. Throws InputError naming the
// file when it is missing, truncated, not a view data file, of another
// format version, or made for another view, mesh, model or options.
ViewSamples read_view_data(const std::filesystem::path& file, const ViewDataKey& key);

}  // namespace hos::texture
