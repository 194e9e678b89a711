// A textured mesh as the project's renderer sees it, for tests that re-render
// a texturing result (render/rasterizer.h) and compare with true images.
#pragma once

#include "render/rasterizer.h"
#include "texture/textured_mesh.h"

namespace hos::testing {

// One triangle per index triple of every atlas page, with per-corner UVs and
// the page as the face's texture.
render::RenderObject as_render_object(const texture::TexturedMesh& textured);

}  // namespace hos::testing
