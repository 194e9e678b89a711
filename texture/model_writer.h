// The textured model in the format its file name's extension chooses:
// .glb (binary glTF), .gltf (+ .bin + atlas images), .obj (+ .mtl + atlas
// images) or .ply (binary, per-face UVs and vertex colours, MeshLab's
// "comment TextureFile" for the atlas images). Every format comes from the
// same TexturedMesh and the same encoded atlases; the files beside the model
// are named after its stem (out.obj: out.mtl, out_atlas0.jpg).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "texture/gltf_writer.h"
#include "texture/image_encoding.h"
#include "texture/textured_mesh.h"

namespace hos::texture {

enum class ModelFormat { kGlb, kGltf, kObj, kPly };

// The format of a model file by its extension (case-insensitive), or none.
std::optional<ModelFormat> model_format_of(const std::filesystem::path& path);

// "a .glb, .gltf, .obj or .ply file": for error messages.
const char* model_formats_text();

// Writes path (and its companion files). Throws ConfigError for an unknown
// extension, OutputError if a file cannot be written.
void write_model(const std::filesystem::path& path, const TexturedMesh& mesh, const GltfWriteOptions& options);
// mesh_compression as GltfWriteOptions has it (glTF formats only).
void write_model(const std::filesystem::path& path,
                 const TexturedMesh& mesh,
                 const std::vector<EncodedImage>& images,
                 const std::string& mesh_compression = "none");

// A .glb this project wrote, read back (its atlases' encoded bytes kept and
// decoded), so a finished model can be written in another format without
// encoding its images again. Throws InputError naming the file.
struct StoredModel {
  TexturedMesh mesh;
  std::vector<EncodedImage> images;
};
StoredModel read_glb_model(const std::filesystem::path& path);

// The preview model's file beside a model: out.glb -> out.preview.glb (any
// extension; the preview is always a .glb).
std::filesystem::path preview_model_path(const std::filesystem::path& model);

// Copies the workspace's .glb to target in target's format.
void convert_model(const std::filesystem::path& glb, const std::filesystem::path& target);

}  // namespace hos::texture
