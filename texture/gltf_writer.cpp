#include "texture/gltf_writer.h"

#include <tiny_gltf.h>

#include <cstring>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/error.h"

namespace hos::texture {

namespace {

// Appends bytes to the single buffer, 4-byte aligned, and returns a new
// bufferView index.
int add_buffer_view(tinygltf::Model& model, const void* data, std::size_t size, int target) {
  auto& buffer = model.buffers[0].data;
  while (buffer.size() % 4 != 0) buffer.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buffer.size();
  view.byteLength = size;
  view.target = target;
  const auto* bytes = static_cast<const unsigned char*>(data);
  buffer.insert(buffer.end(), bytes, bytes + size);
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

// Accessors of the vertex attributes every primitive shares.
struct VertexAccessors {
  int position = -1, normal = -1, uv = -1;
};

int add_float_accessor(tinygltf::Model& model,
                       const std::vector<float>& values,
                       int type,
                       std::size_t count,
                       std::vector<double> min = {},
                       std::vector<double> max = {}) {
  return add_accessor(model, add_buffer_view(model, values.data(), values.size() * 4, TINYGLTF_TARGET_ARRAY_BUFFER),
                      TINYGLTF_COMPONENT_TYPE_FLOAT, type, count, std::move(min), std::move(max));
}

VertexAccessors add_vertex_attributes(tinygltf::Model& model, const TexturedMesh& mesh) {
  const std::size_t n = mesh.positions.size();
  VertexAccessors out;
  std::vector<float> flat;
  flat.reserve(3 * n);
  // glTF requires the positions' bounds.
  std::vector<double> lo(3, 1e300), hi(3, -1e300);
  for (const auto& p : mesh.positions) {
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(p[k])) throw std::invalid_argument("write_glb: non-finite position");
      flat.push_back(p[k]);
      lo[k] = std::min<double>(lo[k], p[k]);
      hi[k] = std::max<double>(hi[k], p[k]);
    }
  }
  if (n == 0) lo = hi = {0.0, 0.0, 0.0};
  out.position = add_float_accessor(model, flat, TINYGLTF_TYPE_VEC3, n, lo, hi);
  flat.clear();
  for (const auto& v : mesh.normals) {
    const Eigen::Vector3f u = v.norm() > 0.0f ? Eigen::Vector3f(v.normalized()) : Eigen::Vector3f(0, 0, 1);
    flat.insert(flat.end(), {u.x(), u.y(), u.z()});
  }
  out.normal = add_float_accessor(model, flat, TINYGLTF_TYPE_VEC3, n);
  flat.clear();
  for (const auto& uv : mesh.uvs) flat.insert(flat.end(), {uv.x(), uv.y()});
  out.uv = add_float_accessor(model, flat, TINYGLTF_TYPE_VEC2, n);
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

// The page's atlas encoded into the buffer, its texture (sampler 0) and
// material; returns the material's index.
int add_page_material(tinygltf::Model& model,
                      const cv::Mat& atlas,
                      std::size_t page,
                      const GltfWriteOptions& options,
                      const std::filesystem::path& path) {
  const bool jpeg = options.image_format == "jpeg";
  std::vector<unsigned char> encoded;
  std::vector<int> params;
  if (jpeg) params = {cv::IMWRITE_JPEG_QUALITY, options.jpeg_quality};
  if (!cv::imencode(jpeg ? ".jpg" : ".png", atlas, encoded, params)) {
    throw OutputError(path.string(), "cannot encode the texture atlas");
  }
  tinygltf::Image image;
  image.name = "atlas" + std::to_string(page);
  image.mimeType = jpeg ? "image/jpeg" : "image/png";
  image.bufferView = add_buffer_view(model, encoded.data(), encoded.size(), 0);
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
tinygltf::Primitive page_primitive(tinygltf::Model& model,
                                   const std::vector<std::uint32_t>& indices,
                                   std::size_t num_vertices,
                                   const VertexAccessors& vertices,
                                   int material) {
  for (std::uint32_t index : indices) {
    if (index >= num_vertices) throw std::invalid_argument("write_glb: index out of range");
  }
  const int index_accessor = add_accessor(
      model, add_buffer_view(model, indices.data(), indices.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
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
// and the default scene; a mesh without primitives is left out.
void add_scene(tinygltf::Model& model, tinygltf::Mesh gltf_mesh, const Eigen::Matrix4d& root_matrix) {
  gltf_mesh.name = "textured_mesh";
  const bool has_mesh = !gltf_mesh.primitives.empty();
  if (has_mesh) model.meshes.push_back(std::move(gltf_mesh));
  tinygltf::Node node;
  node.name = "hos_model";
  if (has_mesh) node.mesh = 0;
  if (!root_matrix.isIdentity(1e-12)) {
    node.matrix.assign(root_matrix.data(), root_matrix.data() + 16);  // column-major
  }
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.name = "scene";
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;
}

void serialize(tinygltf::Model& model, const std::filesystem::path& path) {
  write_atomically(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw OutputError(path.string(), "cannot open for writing");
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&model, out, false, true)) {
      throw OutputError(path.string(), "tinygltf could not serialize the model");
    }
    out.flush();
    if (!out) throw OutputError(path.string(), "write failed");
  });
}

}  // namespace

void write_glb(const std::filesystem::path& path, const TexturedMesh& mesh, const GltfWriteOptions& options) {
  check_mesh(mesh);
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "hos";
  model.buffers.emplace_back();
  const VertexAccessors vertices = add_vertex_attributes(model, mesh);
  add_sampler(model);
  tinygltf::Mesh gltf_mesh;
  for (std::size_t page = 0; page < mesh.atlases.size(); ++page) {
    if (mesh.indices[page].empty()) continue;
    const int material = add_page_material(model, mesh.atlases[page], page, options, path);
    gltf_mesh.primitives.push_back(
        page_primitive(model, mesh.indices[page], mesh.positions.size(), vertices, material));
  }
  while (model.buffers[0].data.size() % 4 != 0) model.buffers[0].data.push_back(0);
  add_scene(model, std::move(gltf_mesh), mesh.root_matrix);
  serialize(model, path);
}

}  // namespace hos::texture
