#include "eval/gltf_reader.h"

#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <unordered_map>

#include "core/error.h"
#include "core/glb_container.h"

namespace hos::eval {
namespace {

// Decodes embedded images with OpenCV into 8-bit BGR (component 3).
bool decode_image(tinygltf::Image* image,
                  const int /*index*/,
                  std::string* err,
                  std::string* /*warn*/,
                  int /*req_width*/,
                  int /*req_height*/,
                  const unsigned char* bytes,
                  int size,
                  void* /*user*/) {
  const cv::Mat encoded(1, size, CV_8U, const_cast<unsigned char*>(bytes));
  const cv::Mat decoded = cv::imdecode(encoded, cv::IMREAD_COLOR);
  if (decoded.empty()) {
    if (err != nullptr) *err += "an embedded image could not be decoded";
    return false;
  }
  const cv::Mat bgr = decoded.isContinuous() ? decoded : decoded.clone();
  image->width = bgr.cols;
  image->height = bgr.rows;
  image->component = 3;
  image->bits = 8;
  image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image->image.assign(bgr.data, bgr.data + bgr.total() * 3);
  return true;
}

class AccessorReader {
 public:
  AccessorReader(const tinygltf::Model& model, int accessor_index, const std::string& path) : path_(path) {
    if (accessor_index < 0 || accessor_index >= static_cast<int>(model.accessors.size())) {
      throw InputError(path, "an accessor index is out of range");
    }
    accessor_ = &model.accessors[accessor_index];
    if (accessor_->bufferView < 0 || accessor_->bufferView >= static_cast<int>(model.bufferViews.size())) {
      throw InputError(path, "an accessor without a valid buffer view (sparse accessors are not supported)");
    }
    const tinygltf::BufferView& view = model.bufferViews[accessor_->bufferView];
    const tinygltf::Buffer& buffer = model.buffers.at(view.buffer);
    components_ = tinygltf::GetNumComponentsInType(accessor_->type);
    component_size_ = tinygltf::GetComponentSizeInBytes(accessor_->componentType);
    if (components_ <= 0 || component_size_ <= 0) throw InputError(path, "an accessor has an unknown type");
    stride_ = view.byteStride > 0 ? view.byteStride : components_ * component_size_;
    data_ = buffer.data.data() + view.byteOffset + accessor_->byteOffset;
    const std::size_t needed =
        accessor_->count == 0 ? 0 : (accessor_->count - 1) * stride_ + components_ * component_size_;
    if (view.byteOffset + accessor_->byteOffset + needed > buffer.data.size()) {
      throw InputError(path, "an accessor reads past the end of its buffer");
    }
  }
  std::size_t count() const { return accessor_->count; }
  int components() const { return components_; }
  double get(std::size_t i, int c) const {
    const unsigned char* p = data_ + i * stride_ + c * component_size_;
    double v = 0.0;
    switch (accessor_->componentType) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float f;
        std::memcpy(&f, p, 4);
        v = f;
        break;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        std::uint32_t u;
        std::memcpy(&u, p, 4);
        v = u;
        break;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t u;
        std::memcpy(&u, p, 2);
        v = u;
        break;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        v = *p;
        break;
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        std::int16_t s;
        std::memcpy(&s, p, 2);
        v = s;
        break;
      }
      case TINYGLTF_COMPONENT_TYPE_BYTE:
        v = static_cast<std::int8_t>(*p);
        break;
      default:
        throw InputError(path_, "an accessor has an unsupported component type");
    }
    if (accessor_->normalized) {
      if (accessor_->componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) v /= 255.0;
      if (accessor_->componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) v /= 65535.0;
      if (accessor_->componentType == TINYGLTF_COMPONENT_TYPE_BYTE) v = std::max(v / 127.0, -1.0);
      if (accessor_->componentType == TINYGLTF_COMPONENT_TYPE_SHORT) v = std::max(v / 32767.0, -1.0);
    }
    return v;
  }

 private:
  std::string path_;
  const tinygltf::Accessor* accessor_ = nullptr;
  const unsigned char* data_ = nullptr;
  int components_ = 0, component_size_ = 0;
  std::size_t stride_ = 0;
};

Eigen::Matrix4d local_matrix(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) return Eigen::Map<const Eigen::Matrix4d>(node.matrix.data());  // column-major
  Eigen::Affine3d m = Eigen::Affine3d::Identity();
  if (node.translation.size() == 3)
    m.translate(Eigen::Vector3d(node.translation[0], node.translation[1], node.translation[2]));
  if (node.rotation.size() == 4) {
    m.rotate(Eigen::Quaterniond(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]).normalized());
  }
  if (node.scale.size() == 3) m.scale(Eigen::Vector3d(node.scale[0], node.scale[1], node.scale[2]));
  return m.matrix();
}

struct Builder {
  const tinygltf::Model& model;
  std::string path;
  render::RenderObject out;
  std::unordered_map<int, int> texture_of_image;  // glTF image -> Material texture
  std::unordered_map<std::string, int> weld;      // position bits -> vertex

  int texture_for(const tinygltf::Primitive& prim) {
    Eigen::Vector4d factor(1, 1, 1, 1);
    if (prim.material >= 0 && prim.material < static_cast<int>(model.materials.size())) {
      const auto& pbr = model.materials[prim.material].pbrMetallicRoughness;
      if (pbr.baseColorFactor.size() == 4) {
        factor = Eigen::Vector4d(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2], 1);
      }
      const int tex = pbr.baseColorTexture.index;
      if (tex >= 0 && tex < static_cast<int>(model.textures.size())) {
        const int source = model.textures[tex].source;
        if (source < 0 || source >= static_cast<int>(model.images.size())) {
          throw InputError(path, "a texture refers to a missing image");
        }
        if (auto it = texture_of_image.find(source); it != texture_of_image.end()) return it->second;
        const tinygltf::Image& image = model.images[source];
        if (image.component != 3 || image.image.size() != static_cast<std::size_t>(image.width) * image.height * 3) {
          throw InputError(path, "image " + std::to_string(source) + " was not decoded");
        }
        cv::Mat bgr(image.height, image.width, CV_8UC3);
        std::memcpy(bgr.data, image.image.data(), image.image.size());
        out.material.textures.push_back(bgr);
        texture_of_image[source] = static_cast<int>(out.material.textures.size()) - 1;
        return texture_of_image[source];
      }
    }
    // Untextured: a 1x1 texture of the base colour (factor is linear; texels are sRGB).
    auto to_srgb = [](double c) {
      c = std::clamp(c, 0.0, 1.0);
      const double s = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
      return static_cast<unsigned char>(std::lround(255.0 * s));
    };
    out.material.textures.push_back(
        cv::Mat(1, 1, CV_8UC3, cv::Scalar(to_srgb(factor[2]), to_srgb(factor[1]), to_srgb(factor[0]))));
    return static_cast<int>(out.material.textures.size()) - 1;
  }

  int vertex_for(const Eigen::Vector3f& p) {
    std::string key(reinterpret_cast<const char*>(p.data()), sizeof(float) * 3);
    const auto [it, inserted] = weld.emplace(key, static_cast<int>(out.mesh.vertices.size()));
    if (inserted) out.mesh.vertices.push_back(p);
    return it->second;
  }

  void add_primitive(const tinygltf::Primitive& prim, const Eigen::Matrix4d& world) {
    if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) {
      throw InputError(path, "only triangle-list primitives are supported");
    }
    const auto pos_it = prim.attributes.find("POSITION");
    if (pos_it == prim.attributes.end()) throw InputError(path, "a primitive has no POSITION attribute");
    const AccessorReader positions(model, pos_it->second, path);
    if (positions.components() != 3) throw InputError(path, "POSITION is not VEC3");
    std::vector<int> vertex(positions.count());
    for (std::size_t i = 0; i < positions.count(); ++i) {
      const Eigen::Vector4d x(positions.get(i, 0), positions.get(i, 1), positions.get(i, 2), 1.0);
      const Eigen::Vector3f w = (world * x).head<3>().cast<float>();
      if (!w.allFinite()) throw InputError(path, "a vertex position is not finite");
      vertex[i] = vertex_for(w);
    }
    std::vector<Eigen::Vector2f> uv;
    if (const auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end()) {
      const AccessorReader r(model, it->second, path);
      if (r.components() != 2 || r.count() != positions.count()) throw InputError(path, "TEXCOORD_0 is malformed");
      uv.resize(r.count());
      for (std::size_t i = 0; i < r.count(); ++i) uv[i] = Eigen::Vector2f(r.get(i, 0), r.get(i, 1));
    }
    std::vector<std::size_t> indices;
    if (prim.indices >= 0) {
      const AccessorReader r(model, prim.indices, path);
      for (std::size_t i = 0; i < r.count(); ++i) indices.push_back(static_cast<std::size_t>(r.get(i, 0)));
    } else {
      for (std::size_t i = 0; i < positions.count(); ++i) indices.push_back(i);
    }
    if (indices.size() % 3 != 0) throw InputError(path, "a triangle list has a length not divisible by 3");
    const int texture = texture_for(prim);
    // A mirroring node transform flips the winding; keep faces counter-clockwise.
    const bool flip = world.topLeftCorner<3, 3>().determinant() < 0.0;
    for (std::size_t f = 0; f < indices.size(); f += 3) {
      int corner[3] = {0, 1, 2};
      if (flip) std::swap(corner[1], corner[2]);
      Eigen::Vector3i face;
      for (int c = 0; c < 3; ++c) {
        const std::size_t i = indices[f + corner[c]];
        if (i >= positions.count()) throw InputError(path, "a vertex index is out of range");
        face[c] = vertex[i];
        out.material.corner_uvs.push_back(uv.empty() ? Eigen::Vector2f(0.5f, 0.5f) : uv[i]);
      }
      out.mesh.faces.push_back(face);
      out.material.face_texture.push_back(texture);
    }
  }

  void add_node(int index, const Eigen::Matrix4d& parent, int depth) {
    if (index < 0 || index >= static_cast<int>(model.nodes.size()) || depth > 64) {
      throw InputError(path, "the node hierarchy is malformed");
    }
    const tinygltf::Node& node = model.nodes[index];
    const Eigen::Matrix4d world = parent * local_matrix(node);
    if (node.mesh >= 0) {
      if (node.mesh >= static_cast<int>(model.meshes.size())) throw InputError(path, "a node refers to a missing mesh");
      for (const auto& prim : model.meshes[node.mesh].primitives) add_primitive(prim, world);
    }
    for (int child : node.children) add_node(child, world, depth + 1);
  }
};

}  // namespace

render::RenderObject read_glb(const std::filesystem::path& path, GlbFrame frame) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path.string(), "no such file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "cannot be opened");
  // EXT_meshopt_compression is decoded here: tinygltf does not read it.
  const std::string glb = decode_meshopt_glb(
      std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()), path.string());
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&decode_image, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  if (!loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(glb.data()),
                                   static_cast<unsigned int>(glb.size()))) {
    throw InputError(path.string(), "not a readable binary glTF: " + err);
  }
  Builder builder{model, path.string(), {}, {}, {}};
  std::vector<int> roots;
  if (!model.scenes.empty()) {
    const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
    roots = model.scenes.at(scene).nodes;
  } else {
    for (int i = 0; i < static_cast<int>(model.nodes.size()); ++i) roots.push_back(i);
  }
  for (int root : roots) {
    Eigen::Matrix4d start = Eigen::Matrix4d::Identity();
    if (frame == GlbFrame::kModel && root >= 0 && root < static_cast<int>(model.nodes.size())) {
      // Cancels the root's own matrix: its children and meshes stay in the model frame.
      start = local_matrix(model.nodes[root]).inverse();
    }
    builder.add_node(root, start, 0);
  }
  if (builder.out.mesh.faces.empty()) throw InputError(path.string(), "the glTF holds no triangles");
  return std::move(builder.out);
}

}  // namespace hos::eval
