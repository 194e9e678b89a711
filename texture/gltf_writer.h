// glTF 2.0 output with tinygltf: one mesh with a primitive per atlas page
// (POSITION, NORMAL, TEXCOORD_0, indices), the atlases as JPEG or PNG
// (embedded in buffer views of a .glb; files beside a .gltf), a PBR material per page (baseColorTexture,
// metallic 0, roughness 1, double-sided false), asset.generator "hos",
// asset.extras the root frame's "units" ("metres" or "arbitrary") and, when
// GPS placed the model, "geo_origin" (texture/placement.h).
// Vertices stay in the SfM model frame; the single root node carries
// TexturedMesh::root_matrix (identity is written as no matrix).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "texture/image_encoding.h"
#include "texture/textured_mesh.h"

namespace hos::texture {

struct GltfWriteOptions {
  std::string image_format = "jpeg";  // jpeg | png
  int jpeg_quality = 95;
  // "quantized": KHR_mesh_quantization (16-bit positions and UVs, 8-bit
  // normals; a required extension, so readers without it refuse the file);
  // "none": 32-bit floats.
  std::string mesh_compression = "none";
};

// Every atlas encoded as the options say; OutputError (naming path) if one
// cannot be.
std::vector<EncodedImage> encode_atlases(const TexturedMesh& mesh,
                                         const GltfWriteOptions& options,
                                         const std::filesystem::path& path);

// The file name of page's atlas beside a model named stem: stem_atlasN.jpg.
std::string atlas_file_name(const std::string& stem, std::size_t page, const EncodedImage& image);

// Writes atomically. Throws OutputError if the file cannot be written or an
// image cannot be encoded; std::invalid_argument for an inconsistent mesh
// (images: one per atlas).
void write_glb(const std::filesystem::path& path, const TexturedMesh& mesh, const GltfWriteOptions& options = {});
void write_glb(const std::filesystem::path& path,
               const TexturedMesh& mesh,
               const std::vector<EncodedImage>& images,
               const std::string& mesh_compression = "none");

// A .gltf (JSON) with its buffer in STEM.bin and the atlases in
// STEM_atlasN.jpg (or .png) in the same folder, STEM being path's stem.
void write_gltf(const std::filesystem::path& path,
                const TexturedMesh& mesh,
                const std::vector<EncodedImage>& images,
                const std::string& mesh_compression = "none");

}  // namespace hos::texture
