// Reading a binary glTF (.glb) back into a mesh and material for measuring:
// node transforms are applied (so the mesh is in the coordinates the root
// node maps it to, i.e. the SfM/world frame of hos-texture's output), and
// vertices at exactly the same position are welded so topology checks see
// the surface rather than the UV seams.
#pragma once

#include <filesystem>

#include "render/rasterizer.h"

namespace hos {

// Throws InputError naming the file for a missing/malformed file, a primitive
// that is not a triangle list, or an image that cannot be decoded. Base-colour
// textures are decoded with OpenCV (BGR); a primitive without a texture gets a
// 1x1 texture of its base colour factor so every face has a texture.
RenderObject read_glb(const std::filesystem::path& path);

}  // namespace hos
