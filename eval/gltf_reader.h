// Reading a binary glTF (.glb) back into a mesh and material for measuring.
// hos-texture keeps vertices in the SfM model's frame and puts the viewer's
// up-axis conversion into the root node's matrix, so by default the root
// nodes' own matrices are left out (GlbFrame::kModel: the SfM frame) while
// transforms below the roots apply; GlbFrame::kScene applies every node
// transform (the frame a viewer shows). Vertices at exactly the same position are welded so topology checks see
// the surface rather than the UV seams. Quantized (KHR_mesh_quantization)
// and meshopt-compressed (EXT_meshopt_compression) files are read as well.
#pragma once

#include <filesystem>

#include "render/rasterizer.h"

namespace hos::eval {

// Throws InputError naming the file for a missing/malformed file, a primitive
// that is not a triangle list, or an image that cannot be decoded. Base-colour
// textures are decoded with OpenCV (BGR); a primitive without a texture gets a
// 1x1 texture of its base colour factor so every face has a texture.
enum class GlbFrame { kModel, kScene };
render::RenderObject read_glb(const std::filesystem::path& path, GlbFrame frame = GlbFrame::kModel);

}  // namespace hos::eval
