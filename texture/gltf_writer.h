// Binary glTF 2.0 output with tinygltf: one mesh with a primitive per atlas
// page (POSITION, NORMAL, TEXCOORD_0, indices), the atlases embedded as PNG
// or JPEG in buffer views, a PBR material per page (baseColorTexture,
// metallic 0, roughness 1, double-sided false), asset.generator "hos".
// Vertices stay in the SfM model frame; the single root node carries
// TexturedMesh::root_matrix (identity is written as no matrix).
#pragma once

#include <filesystem>
#include <string>

#include "texture/textured_mesh.h"

namespace hos::texture {

struct GltfWriteOptions {
  std::string image_format = "png";  // png | jpeg
  int jpeg_quality = 90;
};

// Writes atomically. Throws OutputError if the file cannot be written or an
// image cannot be encoded; std::invalid_argument for an inconsistent mesh.
void write_glb(const std::filesystem::path& path, const TexturedMesh& mesh, const GltfWriteOptions& options = {});

}  // namespace hos::texture
