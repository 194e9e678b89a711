#include "tests/support/textured_render.h"

namespace hos::testing {

render::RenderObject as_render_object(const texture::TexturedMesh& textured) {
  render::RenderObject object;
  object.mesh.vertices = textured.positions;
  object.material.textures = textured.atlases;
  for (std::size_t page = 0; page < textured.indices.size(); ++page) {
    const auto& idx = textured.indices[page];
    for (std::size_t i = 0; i + 2 < idx.size(); i += 3) {
      object.mesh.faces.emplace_back(idx[i], idx[i + 1], idx[i + 2]);
      for (int c = 0; c < 3; ++c) object.material.corner_uvs.push_back(textured.uvs[idx[i + c]]);
      object.material.face_texture.push_back(static_cast<int>(page));
    }
  }
  return object;
}

}  // namespace hos::testing
