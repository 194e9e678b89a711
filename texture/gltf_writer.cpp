#include "texture/gltf_writer.h"

#include <meshoptimizer.h>
#include <tiny_gltf.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/glb_container.h"
#include "texture/image_encoding.h"

namespace hos::texture {

namespace {

constexpr const char* kMeshopt = "EXT_meshopt_compression";

// A buffer view compressed with EXT_meshopt_compression: its stream lies in
// buffer 0, the view itself in the fallback buffer 1, which holds no data.
struct CompressedView {
  int view = -1;
  std::size_t offset = 0, length = 0, stride = 0, count = 0;
  const char* mode = "";
};

// The glTF model being built; with meshopt, its vertex and index views are
// compressed as they are added.
struct ModelBuilder {
  tinygltf::Model model;
  bool meshopt = false;
  std::vector<CompressedView> compressed;
  std::size_t fallback_length = 0;
};

std::size_t aligned4(std::size_t n) { return (n + 3) / 4 * 4; }

// Appends bytes to buffer 0, 4-byte aligned; returns their offset.
std::size_t append_to_buffer(tinygltf::Model& model, const void* data, std::size_t size) {
  auto& buffer = model.buffers[0].data;
  buffer.resize(aligned4(buffer.size()), 0);
  const std::size_t offset = buffer.size();
  const auto* bytes = static_cast<const unsigned char*>(data);
  buffer.insert(buffer.end(), bytes, bytes + size);
  return offset;
}

// meshoptimizer's stream of a view's data: uint32 triangle indices (target
// ELEMENT_ARRAY_BUFFER) or vertices of stride bytes; sets view's stride,
// count and mode.
std::vector<unsigned char> encode_meshopt(
    const void* data, std::size_t size, int target, std::size_t stride, CompressedView& view) {
  std::vector<unsigned char> encoded;
  if (target == TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER) {
    const auto* indices = static_cast<const unsigned int*>(data);
    view.count = size / 4;
    view.stride = 4;
    view.mode = "TRIANGLES";
    const unsigned int largest = view.count == 0 ? 0u : *std::max_element(indices, indices + view.count);
    encoded.resize(meshopt_encodeIndexBufferBound(view.count, std::size_t{largest} + 1));
    encoded.resize(meshopt_encodeIndexBuffer(encoded.data(), encoded.size(), indices, view.count));
  } else {
    view.count = size / stride;
    view.stride = stride;
    view.mode = "ATTRIBUTES";
    encoded.resize(meshopt_encodeVertexBufferBound(view.count, stride));
    encoded.resize(meshopt_encodeVertexBuffer(encoded.data(), encoded.size(), data, view.count, stride));
  }
  if (encoded.empty()) throw std::logic_error("meshoptimizer could not encode a buffer view");
  return encoded;
}

// Adds a bufferView of size bytes and returns its index. Image bytes (target
// 0) and, without meshopt, all data go into buffer 0; with meshopt, vertex
// and index data are compressed into buffer 0 and the view lies in the
// fallback buffer 1.
int add_buffer_view(ModelBuilder& builder, const void* data, std::size_t size, int target, int stride = 0) {
  tinygltf::Model& model = builder.model;
  tinygltf::BufferView view;
  view.byteLength = size;
  view.target = target;
  view.byteStride = stride;
  if (builder.meshopt && target != 0) {
    CompressedView compressed;
    const std::vector<unsigned char> encoded =
        encode_meshopt(data, size, target, static_cast<std::size_t>(stride), compressed);
    compressed.offset = append_to_buffer(model, encoded.data(), encoded.size());
    compressed.length = encoded.size();
    compressed.view = static_cast<int>(model.bufferViews.size());
    builder.compressed.push_back(compressed);
    view.buffer = 1;
    view.byteOffset = aligned4(builder.fallback_length);
    builder.fallback_length = view.byteOffset + size;
  } else {
    view.buffer = 0;
    view.byteOffset = append_to_buffer(model, data, size);
  }
  model.bufferViews.push_back(view);
  return static_cast<int>(model.bufferViews.size()) - 1;
}

int add_accessor(tinygltf::Model& model,
                 int buffer_view,
                 int component_type,
                 int type,
                 std::size_t count,
                 std::vector<double> min = {},
                 std::vector<double> max = {}) {
  tinygltf::Accessor accessor;
  accessor.bufferView = buffer_view;
  accessor.byteOffset = 0;
  accessor.componentType = component_type;
  accessor.type = type;
  accessor.count = count;
  accessor.minValues = std::move(min);
  accessor.maxValues = std::move(max);
  model.accessors.push_back(accessor);
  return static_cast<int>(model.accessors.size()) - 1;
}

void check_mesh(const TexturedMesh& mesh) {
  const std::size_t n = mesh.positions.size();
  if (mesh.normals.size() != n || mesh.uvs.size() != n) {
    throw std::invalid_argument("write_glb: positions, normals and uvs differ in length");
  }
  if (mesh.indices.size() != mesh.atlases.size()) {
    throw std::invalid_argument("write_glb: one index list per atlas is required");
  }
}

// Accessors of the vertex attributes every primitive shares; with
// quantized positions, the matrix that maps them back into the model frame.
struct VertexAccessors {
  int position = -1, normal = -1, uv = -1;
  std::optional<Eigen::Matrix4d> dequantize;
};

int add_float_accessor(ModelBuilder& builder,
                       const std::vector<float>& values,
                       int type,
                       std::size_t count,
                       std::vector<double> min = {},
                       std::vector<double> max = {}) {
  return add_accessor(builder.model,
                      add_buffer_view(builder, values.data(), values.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER),
                      TINYGLTF_COMPONENT_TYPE_FLOAT, type, count, std::move(min), std::move(max));
}

Eigen::Vector3f unit_normal(const Eigen::Vector3f& v) {
  return v.norm() > 0.0f ? Eigen::Vector3f(v.normalized()) : Eigen::Vector3f(0, 0, 1);
}

// The positions' bounds (glTF requires them); finite positions only.
void position_bounds(const TexturedMesh& mesh, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  lo = Eigen::Vector3d::Constant(1e300);
  hi = Eigen::Vector3d::Constant(-1e300);
  for (const auto& p : mesh.positions) {
    if (!p.allFinite()) throw std::invalid_argument("write_glb: non-finite position");
    lo = lo.cwiseMin(p.cast<double>());
    hi = hi.cwiseMax(p.cast<double>());
  }
  if (mesh.positions.empty()) lo = hi = Eigen::Vector3d::Zero();
}

VertexAccessors add_float_attributes(ModelBuilder& builder, const TexturedMesh& mesh) {
  const std::size_t n = mesh.positions.size();
  VertexAccessors out;
  Eigen::Vector3d lo, hi;
  position_bounds(mesh, lo, hi);
  std::vector<float> flat;
  flat.reserve(3 * n);
  for (const auto& p : mesh.positions) flat.insert(flat.end(), {p.x(), p.y(), p.z()});
  out.position =
      add_float_accessor(builder, flat, TINYGLTF_TYPE_VEC3, n, {lo.x(), lo.y(), lo.z()}, {hi.x(), hi.y(), hi.z()});
  flat.clear();
  for (const auto& v : mesh.normals) {
    const Eigen::Vector3f u = unit_normal(v);
    flat.insert(flat.end(), {u.x(), u.y(), u.z()});
  }
  out.normal = add_float_accessor(builder, flat, TINYGLTF_TYPE_VEC3, n);
  flat.clear();
  for (const auto& uv : mesh.uvs) flat.insert(flat.end(), {uv.x(), uv.y()});
  out.uv = add_float_accessor(builder, flat, TINYGLTF_TYPE_VEC2, n);
  return out;
}

// KHR_mesh_quantization: positions as unsigned 16-bit integers on a grid of
// equal steps over the bounding box's longest side (a node's matrix scales
// and moves them back; one step for all axes keeps the normals' directions),
// normals as normalized signed bytes, UVs as normalized unsigned 16-bit
// integers. Vertex elements padded to 4 bytes as glTF requires.
VertexAccessors add_quantized_attributes(ModelBuilder& builder, const TexturedMesh& mesh) {
  tinygltf::Model& model = builder.model;
  constexpr double kLevels = 65535.0;
  const std::size_t n = mesh.positions.size();
  VertexAccessors out;
  Eigen::Vector3d lo, hi;
  position_bounds(mesh, lo, hi);
  const double step = std::max((hi - lo).maxCoeff(), 1e-30) / kLevels;
  std::vector<std::uint16_t> positions;
  positions.reserve(4 * n);
  std::vector<double> qmin(3, kLevels), qmax(3, 0.0);
  for (const auto& p : mesh.positions) {
    for (int k = 0; k < 3; ++k) {
      const double q = std::clamp(std::round((p[k] - lo[k]) / step), 0.0, kLevels);
      positions.push_back(static_cast<std::uint16_t>(q));
      qmin[k] = std::min(qmin[k], q);
      qmax[k] = std::max(qmax[k], q);
    }
    positions.push_back(0);
  }
  if (n == 0) qmin = qmax = {0.0, 0.0, 0.0};
  out.position = add_accessor(
      model, add_buffer_view(builder, positions.data(), positions.size() * 2, TINYGLTF_TARGET_ARRAY_BUFFER, 8),
      TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC3, n, qmin, qmax);
  std::vector<std::int8_t> normals;
  normals.reserve(4 * n);
  for (const auto& v : mesh.normals) {
    const Eigen::Vector3f u = unit_normal(v);
    for (int k = 0; k < 3; ++k) normals.push_back(static_cast<std::int8_t>(std::lround(127.0f * u[k])));
    normals.push_back(0);
  }
  out.normal =
      add_accessor(model, add_buffer_view(builder, normals.data(), normals.size(), TINYGLTF_TARGET_ARRAY_BUFFER, 4),
                   TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_TYPE_VEC3, n);
  model.accessors[out.normal].normalized = true;
  std::vector<std::uint16_t> uvs;
  uvs.reserve(2 * n);
  for (const auto& uv : mesh.uvs) {
    for (int k = 0; k < 2; ++k) {
      uvs.push_back(static_cast<std::uint16_t>(std::lround(std::clamp(uv[k], 0.0f, 1.0f) * kLevels)));
    }
  }
  out.uv = add_accessor(model, add_buffer_view(builder, uvs.data(), uvs.size() * 2, TINYGLTF_TARGET_ARRAY_BUFFER, 4),
                        TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC2, n);
  model.accessors[out.uv].normalized = true;
  Eigen::Matrix4d dequantize = Eigen::Matrix4d::Identity();
  dequantize.topLeftCorner<3, 3>() *= step;
  dequantize.topRightCorner<3, 1>() = lo;
  out.dequantize = dequantize;
  model.extensionsUsed.push_back("KHR_mesh_quantization");
  model.extensionsRequired.push_back("KHR_mesh_quantization");
  return out;
}

void add_sampler(tinygltf::Model& model) {
  tinygltf::Sampler sampler;
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  sampler.wrapS = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  sampler.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  model.samplers.push_back(sampler);
}

// The page's encoded atlas (in the buffer, or the file uri beside a .gltf),
// its texture (sampler 0) and material; returns the material's index.
int add_page_material(ModelBuilder& builder, const EncodedImage& encoded, std::size_t page, const std::string& uri) {
  tinygltf::Model& model = builder.model;
  tinygltf::Image image;
  image.name = "atlas" + std::to_string(page);
  image.mimeType = encoded.mime_type;
  if (uri.empty()) {
    image.bufferView = add_buffer_view(builder, encoded.bytes.data(), encoded.bytes.size(), 0);
  } else {
    image.uri = uri;
  }
  model.images.push_back(image);
  tinygltf::Texture texture;
  texture.sampler = 0;
  texture.source = static_cast<int>(model.images.size()) - 1;
  model.textures.push_back(texture);

  tinygltf::Material material;
  material.name = "atlas" + std::to_string(page);
  material.pbrMetallicRoughness.baseColorTexture.index = static_cast<int>(model.textures.size()) - 1;
  material.pbrMetallicRoughness.metallicFactor = 0.0;
  material.pbrMetallicRoughness.roughnessFactor = 1.0;
  model.materials.push_back(material);
  return static_cast<int>(model.materials.size()) - 1;
}

// The triangles of one page with their material.
tinygltf::Primitive page_primitive(ModelBuilder& builder,
                                   const std::vector<std::uint32_t>& indices,
                                   std::size_t num_vertices,
                                   const VertexAccessors& vertices,
                                   int material) {
  tinygltf::Model& model = builder.model;
  for (std::uint32_t index : indices) {
    if (index >= num_vertices) throw std::invalid_argument("write_glb: index out of range");
  }
  const int index_accessor = add_accessor(
      model, add_buffer_view(builder, indices.data(), indices.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
      TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, indices.size());
  tinygltf::Primitive primitive;
  primitive.attributes["POSITION"] = vertices.position;
  primitive.attributes["NORMAL"] = vertices.normal;
  primitive.attributes["TEXCOORD_0"] = vertices.uv;
  primitive.indices = index_accessor;
  primitive.material = material;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  return primitive;
}

// The single root node (carrying the root matrix unless it is the identity)
// and the default scene; a mesh without primitives is left out. With
// quantized positions the mesh hangs from a child node whose matrix
// dequantizes them.
void add_scene(tinygltf::Model& model,
               tinygltf::Mesh gltf_mesh,
               const Eigen::Matrix4d& root_matrix,
               const std::optional<Eigen::Matrix4d>& dequantize) {
  gltf_mesh.name = "textured_mesh";
  const bool has_mesh = !gltf_mesh.primitives.empty();
  if (has_mesh) model.meshes.push_back(std::move(gltf_mesh));
  tinygltf::Node node;
  node.name = "hos_model";
  if (!root_matrix.isIdentity(1e-12)) {
    node.matrix.assign(root_matrix.data(), root_matrix.data() + 16);  // column-major
  }
  if (has_mesh && dequantize) {
    node.children.push_back(1);
    model.nodes.push_back(node);
    tinygltf::Node mesh_node;
    mesh_node.name = "hos_mesh";
    mesh_node.mesh = 0;
    mesh_node.matrix.assign(dequantize->data(), dequantize->data() + 16);
    model.nodes.push_back(mesh_node);
  } else {
    if (has_mesh) node.mesh = 0;
    model.nodes.push_back(node);
  }
  tinygltf::Scene scene;
  scene.name = "scene";
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;
}

// asset.extras: the root frame's units and, when GPS placed the model, the
// WGS84 position of its origin (texture/placement.h).
tinygltf::Value placement_extras(const TexturedMesh& mesh) {
  tinygltf::Value::Object extras;
  extras["units"] = tinygltf::Value(std::string(mesh.metric ? "metres" : "arbitrary"));
  if (mesh.geo_origin) {
    tinygltf::Value::Object origin;
    origin["latitude_deg"] = tinygltf::Value(mesh.geo_origin->latitude_deg);
    origin["longitude_deg"] = tinygltf::Value(mesh.geo_origin->longitude_deg);
    if (mesh.geo_origin->altitude_m) origin["altitude_m"] = tinygltf::Value(*mesh.geo_origin->altitude_m);
    origin["axes"] = tinygltf::Value(std::string("+x east, +y up, -z north"));
    extras["geo_origin"] = tinygltf::Value(origin);
  }
  return tinygltf::Value(extras);
}

// The model as a .glb (binary) or as .gltf JSON text.
std::string serialize(tinygltf::Model& model, const std::filesystem::path& path, bool binary) {
  std::ostringstream out;
  tinygltf::TinyGLTF writer;
  writer.SetImageWriter(nullptr, nullptr);  // images are encoded already: keep their uri
  if (!writer.WriteGltfSceneToStream(&model, out, !binary, binary)) {
    throw OutputError(path.string(), "tinygltf could not serialize the model");
  }
  return out.str();
}

// Triangles in vertex-cache order within each page and vertices in the
// order the triangles first use them (meshoptimizer), as the meshopt codecs
// compress best; vertices no triangle uses are left out.
TexturedMesh in_gpu_order(const TexturedMesh& mesh) {
  const std::size_t n = mesh.positions.size();
  TexturedMesh out;
  out.atlases = mesh.atlases;
  out.root_matrix = mesh.root_matrix;
  out.metric = mesh.metric;
  out.geo_origin = mesh.geo_origin;
  std::vector<std::uint32_t> all;
  for (const auto& page : mesh.indices) {
    for (std::uint32_t index : page) {
      if (index >= n) throw std::invalid_argument("write_glb: index out of range");
    }
    out.indices.emplace_back(page.size());
    meshopt_optimizeVertexCache(out.indices.back().data(), page.data(), page.size(), n);
    all.insert(all.end(), out.indices.back().begin(), out.indices.back().end());
  }
  std::vector<std::uint32_t> remap(n);
  const std::size_t used = meshopt_optimizeVertexFetchRemap(remap.data(), all.data(), all.size(), n);
  out.positions.resize(used);
  out.normals.resize(used);
  out.uvs.resize(used);
  for (std::size_t v = 0; v < n; ++v) {
    if (remap[v] == ~0u) continue;
    out.positions[remap[v]] = mesh.positions[v];
    out.normals[remap[v]] = mesh.normals[v];
    out.uvs[remap[v]] = mesh.uvs[v];
  }
  for (auto& page : out.indices) {
    for (std::uint32_t& index : page) index = remap[index];
  }
  return out;
}

// The glTF model of the mesh; with file_stem, images and buffer refer to
// the files file_stem_atlasN.EXT and file_stem.bin (a .gltf), else they are
// embedded (a .glb). With meshopt the mesh is in_gpu_order first.
ModelBuilder build_model(const TexturedMesh& mesh,
                         const std::vector<EncodedImage>& images,
                         const std::string& file_stem,
                         const std::string& mesh_compression) {
  check_mesh(mesh);
  if (images.size() != mesh.atlases.size()) throw std::invalid_argument("write_glb: one image per atlas is required");
  if (mesh_compression != "none" && mesh_compression != "quantized" && mesh_compression != "meshopt") {
    throw std::invalid_argument("write_glb: unknown mesh compression " + mesh_compression);
  }
  ModelBuilder builder;
  builder.meshopt = mesh_compression == "meshopt";
  std::optional<TexturedMesh> reordered;
  if (builder.meshopt) reordered = in_gpu_order(mesh);
  const TexturedMesh& ordered = reordered ? *reordered : mesh;
  tinygltf::Model& model = builder.model;
  model.asset.version = "2.0";
  model.asset.generator = "hos";
  model.asset.extras = placement_extras(mesh);
  model.buffers.emplace_back();
  if (builder.meshopt) {
    model.buffers.emplace_back();  // the fallback buffer: no data
    model.extensionsUsed.push_back(kMeshopt);
    model.extensionsRequired.push_back(kMeshopt);
  }
  const VertexAccessors vertices =
      mesh_compression == "none" ? add_float_attributes(builder, ordered) : add_quantized_attributes(builder, ordered);
  add_sampler(model);
  tinygltf::Mesh gltf_mesh;
  for (std::size_t page = 0; page < ordered.atlases.size(); ++page) {
    if (ordered.indices[page].empty()) continue;
    const std::string uri = file_stem.empty() ? "" : atlas_file_name(file_stem, page, images[page]);
    const int material = add_page_material(builder, images[page], page, uri);
    gltf_mesh.primitives.push_back(
        page_primitive(builder, ordered.indices[page], ordered.positions.size(), vertices, material));
  }
  model.buffers[0].data.resize(aligned4(model.buffers[0].data.size()), 0);
  if (!file_stem.empty()) model.buffers[0].uri = file_stem + ".bin";
  add_scene(model, std::move(gltf_mesh), mesh.root_matrix, vertices.dequantize);
  return builder;
}

// What tinygltf cannot write: the fallback buffer (its length, no data) and
// each compressed view's EXT_meshopt_compression object.
void add_meshopt_json(nlohmann::ordered_json& json, const ModelBuilder& builder) {
  if (!builder.meshopt) return;
  json["buffers"][1] = {{"byteLength", aligned4(builder.fallback_length)},
                        {"extensions", {{kMeshopt, {{"fallback", true}}}}}};
  for (const CompressedView& view : builder.compressed) {
    json["bufferViews"][view.view]["extensions"][kMeshopt] = {
        {"buffer", 0},         {"byteOffset", view.offset}, {"byteLength", view.length}, {"byteStride", view.stride},
        {"count", view.count}, {"mode", view.mode}};
  }
}

}  // namespace

std::string atlas_file_name(const std::string& stem, std::size_t page, const EncodedImage& image) {
  return stem + "_atlas" + std::to_string(page) + image.extension;
}

std::vector<EncodedImage> encode_atlases(const TexturedMesh& mesh,
                                         const GltfWriteOptions& options,
                                         const std::filesystem::path& path) {
  std::vector<EncodedImage> images;
  for (const cv::Mat& atlas : mesh.atlases) {
    try {
      images.push_back(encode_image(atlas, options.image_format, options.jpeg_quality));
    } catch (const std::exception& e) {
      throw OutputError(path.string(), std::string("cannot encode the texture atlas: ") + e.what());
    }
  }
  return images;
}

void write_glb(const std::filesystem::path& path,
               const TexturedMesh& mesh,
               const std::vector<EncodedImage>& images,
               const std::string& mesh_compression) {
  ModelBuilder builder = build_model(mesh, images, "", mesh_compression);
  std::string glb = serialize(builder.model, path, true);
  if (builder.meshopt) {
    const GlbChunks chunks = split_glb(glb, path.string());
    nlohmann::ordered_json json = nlohmann::ordered_json::parse(chunks.json);
    add_meshopt_json(json, builder);
    glb = join_glb(json.dump(), chunks.bin);
  }
  write_bytes(path, glb.data(), glb.size());
}

void write_glb(const std::filesystem::path& path, const TexturedMesh& mesh, const GltfWriteOptions& options) {
  check_mesh(mesh);
  write_glb(path, mesh, encode_atlases(mesh, options, path), options.mesh_compression);
}

void write_gltf(const std::filesystem::path& path,
                const TexturedMesh& mesh,
                const std::vector<EncodedImage>& images,
                const std::string& mesh_compression) {
  const std::string stem = path.stem().string();
  ModelBuilder builder = build_model(mesh, images, stem, mesh_compression);
  const tinygltf::Model& model = builder.model;
  const std::filesystem::path folder = path.parent_path();
  write_bytes(folder / (stem + ".bin"), model.buffers[0].data.data(), model.buffers[0].data.size());
  for (std::size_t page = 0; page < images.size(); ++page) {
    if (mesh.indices[page].empty()) continue;
    write_bytes(folder / atlas_file_name(stem, page, images[page]), images[page].bytes.data(),
                images[page].bytes.size());
  }
  // tinygltf embeds buffers of JSON text as base64 whatever their uri: the
  // JSON's buffer is pointed at the .bin instead.
  nlohmann::ordered_json json = nlohmann::ordered_json::parse(serialize(builder.model, path, false));
  json["buffers"][0] = {{"byteLength", model.buffers[0].data.size()}, {"uri", stem + ".bin"}};
  add_meshopt_json(json, builder);
  const std::string text = json.dump(1) + "\n";
  write_bytes(path, text.data(), text.size());
}

}  // namespace hos::texture
