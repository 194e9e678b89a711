#include "texture/model_writer.h"

#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "core/glb_container.h"

namespace hos::texture {

namespace {

static_assert(std::endian::native == std::endian::little, "the PLY writer writes the host's floats as they are");

// Positions and normals in the viewer's frame: OBJ and PLY have no node to
// carry the root matrix.
struct ViewerFrame {
  std::vector<Eigen::Vector3f> positions, normals;
};

ViewerFrame to_viewer_frame(const TexturedMesh& mesh) {
  const Eigen::Affine3d m(mesh.root_matrix);
  const Eigen::Matrix3d normal_map = m.linear().inverse().transpose();
  ViewerFrame out;
  out.positions.reserve(mesh.positions.size());
  out.normals.reserve(mesh.normals.size());
  for (const auto& p : mesh.positions) out.positions.push_back((m * p.cast<double>()).cast<float>());
  for (const auto& n : mesh.normals) {
    const Eigen::Vector3d v = normal_map * n.cast<double>();
    out.normals.push_back(v.norm() > 0.0 ? Eigen::Vector3f(v.normalized().cast<float>()) : Eigen::Vector3f::UnitZ());
  }
  return out;
}

void check_images(const TexturedMesh& mesh, const std::vector<EncodedImage>& images) {
  if (images.size() != mesh.atlases.size() || mesh.indices.size() != mesh.atlases.size()) {
    throw std::invalid_argument("write_model: one image and one index list per atlas are required");
  }
  if (mesh.normals.size() != mesh.positions.size() || mesh.uvs.size() != mesh.positions.size()) {
    throw std::invalid_argument("write_model: positions, normals and uvs differ in length");
  }
}

void write_atlas_files(const std::filesystem::path& path,
                       const TexturedMesh& mesh,
                       const std::vector<EncodedImage>& images) {
  const std::string stem = path.stem().string();
  for (std::size_t page = 0; page < images.size(); ++page) {
    if (mesh.indices[page].empty()) continue;
    write_bytes(path.parent_path() / atlas_file_name(stem, page, images[page]), images[page].bytes.data(),
                images[page].bytes.size());
  }
}

template <typename... Values>
void append(std::string& out, const char* format, Values... values) {
  char line[128];
  const int n = std::snprintf(line, sizeof line, format, static_cast<double>(values)...);
  out.append(line, static_cast<std::size_t>(std::max(0, n)));
}

// Wavefront OBJ: v, vt (v up from the bottom), vn, one usemtl group per
// page; the .mtl names each page's atlas as map_Kd.
void write_obj(const std::filesystem::path& path, const TexturedMesh& mesh, const std::vector<EncodedImage>& images) {
  const std::string stem = path.stem().string();
  const ViewerFrame frame = to_viewer_frame(mesh);
  std::string mtl = "# hos\n";
  std::string obj = "# hos\nmtllib " + stem + ".mtl\n";
  for (const auto& p : frame.positions) append(obj, "v %.7g %.7g %.7g\n", p.x(), p.y(), p.z());
  for (const auto& uv : mesh.uvs) append(obj, "vt %.7g %.7g\n", uv.x(), 1.0 - uv.y());
  for (const auto& n : frame.normals) append(obj, "vn %.6g %.6g %.6g\n", n.x(), n.y(), n.z());
  for (std::size_t page = 0; page < mesh.indices.size(); ++page) {
    if (mesh.indices[page].empty()) continue;
    const std::string material = "atlas" + std::to_string(page);
    mtl += "newmtl " + material + "\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nd 1\nillum 1\nmap_Kd " +
           atlas_file_name(stem, page, images[page]) + "\n";
    obj += "usemtl " + material + "\n";
    const auto& indices = mesh.indices[page];
    for (std::size_t k = 0; k + 2 < indices.size(); k += 3) {
      char line[128];
      const unsigned a = indices[k] + 1, b = indices[k + 1] + 1, c = indices[k + 2] + 1;
      const int n = std::snprintf(line, sizeof line, "f %u/%u/%u %u/%u/%u %u/%u/%u\n", a, a, a, b, b, b, c, c, c);
      obj.append(line, static_cast<std::size_t>(n));
    }
  }
  write_atlas_files(path, mesh, images);
  write_bytes(path.parent_path() / (stem + ".mtl"), mtl.data(), mtl.size());
  write_bytes(path, obj.data(), obj.size());
}

template <typename T>
void put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

// Binary PLY as MeshLab reads it: "comment TextureFile" per page, per-face
// texcoord (six floats, v up from the bottom) and texnumber, and per-vertex
// colours sampled from the atlas for viewers without textures.
void write_ply(const std::filesystem::path& path, const TexturedMesh& mesh, const std::vector<EncodedImage>& images) {
  const std::string stem = path.stem().string();
  const ViewerFrame frame = to_viewer_frame(mesh);
  std::vector<int> page_of(mesh.positions.size(), -1);
  std::size_t num_faces = 0;
  for (std::size_t page = 0; page < mesh.indices.size(); ++page) {
    for (std::uint32_t i : mesh.indices[page]) page_of[i] = static_cast<int>(page);
    num_faces += mesh.indices[page].size() / 3;
  }
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment hos\n";
  for (std::size_t page = 0; page < images.size(); ++page) {
    out += "comment TextureFile " + atlas_file_name(stem, page, images[page]) + "\n";
  }
  out += "element vertex " + std::to_string(mesh.positions.size()) +
         "\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty "
         "float nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n";
  out += "element face " + std::to_string(num_faces) +
         "\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\nproperty int "
         "texnumber\nend_header\n";
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    for (int k = 0; k < 3; ++k) put<float>(out, frame.positions[v][k]);
    for (int k = 0; k < 3; ++k) put<float>(out, frame.normals[v][k]);
    cv::Vec3b bgr(128, 128, 128);
    if (page_of[v] >= 0) {
      const cv::Mat& atlas = mesh.atlases[page_of[v]];
      const int x = std::clamp(static_cast<int>(mesh.uvs[v].x() * atlas.cols), 0, atlas.cols - 1);
      const int y = std::clamp(static_cast<int>(mesh.uvs[v].y() * atlas.rows), 0, atlas.rows - 1);
      bgr = atlas.at<cv::Vec3b>(y, x);
    }
    put<std::uint8_t>(out, bgr[2]);
    put<std::uint8_t>(out, bgr[1]);
    put<std::uint8_t>(out, bgr[0]);
  }
  for (std::size_t page = 0; page < mesh.indices.size(); ++page) {
    const auto& indices = mesh.indices[page];
    for (std::size_t k = 0; k + 2 < indices.size(); k += 3) {
      put<std::uint8_t>(out, 3);
      for (int c = 0; c < 3; ++c) put<std::int32_t>(out, static_cast<std::int32_t>(indices[k + c]));
      put<std::uint8_t>(out, 6);
      for (int c = 0; c < 3; ++c) {
        put<float>(out, mesh.uvs[indices[k + c]].x());
        put<float>(out, 1.0f - mesh.uvs[indices[k + c]].y());
      }
      put<std::int32_t>(out, static_cast<std::int32_t>(page));
    }
  }
  write_atlas_files(path, mesh, images);
  write_bytes(path, out.data(), out.size());
}

// One component of type component_type at bytes, normalized if asked.
double component_value(const unsigned char* bytes, int component_type, bool normalized) {
  auto read = [bytes](auto value) {
    std::memcpy(&value, bytes, sizeof value);
    return value;
  };
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return read(float{});
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      return read(std::uint32_t{});
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return normalized ? read(std::uint16_t{}) / 65535.0 : read(std::uint16_t{});
    case TINYGLTF_COMPONENT_TYPE_SHORT:
      return normalized ? std::max(read(std::int16_t{}) / 32767.0, -1.0) : read(std::int16_t{});
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return normalized ? read(std::uint8_t{}) / 255.0 : read(std::uint8_t{});
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return normalized ? std::max(read(std::int8_t{}) / 127.0, -1.0) : read(std::int8_t{});
    default:
      throw std::invalid_argument("component_value: unknown component type");
  }
}

// An accessor's values, component by component, as doubles: floats as they
// are, integer components normalized as glTF defines it when the accessor
// is normalized (signed ones clamped to -1), else as integers.
std::vector<double> accessor_values(const tinygltf::Model& model, int index, const std::filesystem::path& path) {
  if (index < 0 || index >= static_cast<int>(model.accessors.size())) {
    throw InputError(path.string(), "a primitive refers to a missing accessor");
  }
  const tinygltf::Accessor& a = model.accessors[index];
  if (a.bufferView < 0 || a.bufferView >= static_cast<int>(model.bufferViews.size())) {
    throw InputError(path.string(), "an accessor without a buffer view");
  }
  const tinygltf::BufferView& view = model.bufferViews[a.bufferView];
  const auto& data = model.buffers.at(view.buffer).data;
  const int components = tinygltf::GetNumComponentsInType(a.type);
  const int size = tinygltf::GetComponentSizeInBytes(a.componentType);
  if (components <= 0 || size <= 0 || a.componentType == TINYGLTF_COMPONENT_TYPE_DOUBLE) {
    throw InputError(path.string(), "an accessor has an unknown type");
  }
  const std::size_t stride = view.byteStride > 0 ? view.byteStride : static_cast<std::size_t>(components * size);
  const std::size_t start = view.byteOffset + a.byteOffset;
  if (a.count > 0 && start + (a.count - 1) * stride + static_cast<std::size_t>(components * size) > data.size()) {
    throw InputError(path.string(), "an accessor reads past the end of its buffer");
  }
  std::vector<double> values;
  values.reserve(a.count * components);
  for (std::size_t i = 0; i < a.count; ++i) {
    for (int c = 0; c < components; ++c) {
      values.push_back(component_value(data.data() + start + i * stride + c * size, a.componentType, a.normalized));
    }
  }
  return values;
}

}  // namespace

std::optional<ModelFormat> model_format_of(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".glb") return ModelFormat::kGlb;
  if (ext == ".gltf") return ModelFormat::kGltf;
  if (ext == ".obj") return ModelFormat::kObj;
  if (ext == ".ply") return ModelFormat::kPly;
  return std::nullopt;
}

const char* model_formats_text() { return "a .glb, .gltf, .obj or .ply file"; }

void write_model(const std::filesystem::path& path,
                 const TexturedMesh& mesh,
                 const std::vector<EncodedImage>& images,
                 const std::string& mesh_compression) {
  const std::optional<ModelFormat> format = model_format_of(path);
  if (!format) throw ConfigError(path.string(), std::string("the output must be ") + model_formats_text());
  check_images(mesh, images);
  switch (*format) {
    case ModelFormat::kGlb:
      write_glb(path, mesh, images, mesh_compression);
      break;
    case ModelFormat::kGltf:
      write_gltf(path, mesh, images, mesh_compression);
      break;
    case ModelFormat::kObj:
      write_obj(path, mesh, images);
      break;
    case ModelFormat::kPly:
      write_ply(path, mesh, images);
      break;
  }
}

void write_model(const std::filesystem::path& path, const TexturedMesh& mesh, const GltfWriteOptions& options) {
  if (!model_format_of(path)) {
    throw ConfigError(path.string(), std::string("the output must be ") + model_formats_text());
  }
  write_model(path, mesh, encode_atlases(mesh, options, path), options.mesh_compression);
}

namespace {

// The root frame's units and geographic origin from asset.extras, as
// gltf_writer.h writes them.
void read_placement_extras(const tinygltf::Value& extras, TexturedMesh& mesh) {
  if (!extras.IsObject()) return;
  const tinygltf::Value& units = extras.Get("units");
  mesh.metric = units.IsString() && units.Get<std::string>() == "metres";
  const tinygltf::Value& origin = extras.Get("geo_origin");
  if (!origin.IsObject()) return;
  const tinygltf::Value& latitude = origin.Get("latitude_deg");
  const tinygltf::Value& longitude = origin.Get("longitude_deg");
  if (!latitude.IsNumber() || !longitude.IsNumber()) return;
  GeoPosition geo;
  geo.latitude_deg = latitude.GetNumberAsDouble();
  geo.longitude_deg = longitude.GetNumberAsDouble();
  const tinygltf::Value& altitude = origin.Get("altitude_m");
  if (altitude.IsNumber()) geo.altitude_m = altitude.GetNumberAsDouble();
  mesh.geo_origin = geo;
}

// The file's bytes with EXT_meshopt_compression decoded, parsed by tinygltf
// (images left encoded).
tinygltf::Model load_glb(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "cannot be opened");
  const std::string glb = decode_meshopt_glb(
      std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()), path.string());
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader([](tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                           void*) { return true; },
                        nullptr);
  std::string error, warning;
  if (!loader.LoadBinaryFromMemory(&model, &error, &warning, reinterpret_cast<const unsigned char*>(glb.data()),
                                   static_cast<unsigned int>(glb.size()))) {
    throw InputError(path.string(), "not a readable binary glTF: " + error);
  }
  return model;
}

// The matrix of the node holding mesh 0 relative to the root node: the
// dequantization of KHR_mesh_quantization's positions (a child of the root,
// as gltf_writer.h writes it), else the identity.
Eigen::Matrix4d mesh_node_matrix(const tinygltf::Model& model) {
  if (model.nodes.empty() || model.nodes[0].mesh == 0) return Eigen::Matrix4d::Identity();
  for (int child : model.nodes[0].children) {
    if (child <= 0 || child >= static_cast<int>(model.nodes.size())) continue;
    const tinygltf::Node& node = model.nodes[child];
    if (node.mesh == 0 && node.matrix.size() == 16) return Eigen::Map<const Eigen::Matrix4d>(node.matrix.data());
  }
  return Eigen::Matrix4d::Identity();
}

// Positions (through the mesh node's matrix), unit normals and UVs of the
// vertices every primitive shares.
void read_vertices(const tinygltf::Model& model, const std::filesystem::path& path, TexturedMesh& mesh) {
  const auto& attributes = model.meshes[0].primitives[0].attributes;
  if (!attributes.count("POSITION") || !attributes.count("NORMAL") || !attributes.count("TEXCOORD_0")) {
    throw InputError(path.string(), "the mesh lacks positions, normals or texture coordinates");
  }
  const std::vector<double> p = accessor_values(model, attributes.at("POSITION"), path);
  const std::vector<double> n = accessor_values(model, attributes.at("NORMAL"), path);
  const std::vector<double> t = accessor_values(model, attributes.at("TEXCOORD_0"), path);
  if (p.size() % 3 != 0 || n.size() != p.size() || t.size() / 2 != p.size() / 3) {
    throw InputError(path.string(), "positions, normals and texture coordinates differ in count or type");
  }
  const Eigen::Affine3d to_model(mesh_node_matrix(model));
  const Eigen::Matrix3d normal_map = to_model.linear().inverse().transpose();
  for (std::size_t i = 0; i + 2 < p.size(); i += 3) {
    mesh.positions.push_back((to_model * Eigen::Vector3d(p[i], p[i + 1], p[i + 2])).cast<float>());
    const Eigen::Vector3d normal = normal_map * Eigen::Vector3d(n[i], n[i + 1], n[i + 2]);
    mesh.normals.push_back(normal.norm() > 0.0 ? Eigen::Vector3f(normal.normalized().cast<float>())
                                               : Eigen::Vector3f::UnitZ());
  }
  for (std::size_t i = 0; i + 1 < t.size(); i += 2) mesh.uvs.emplace_back(t[i], t[i + 1]);
}

// A primitive's triangle indices, checked against the vertex count.
std::vector<std::uint32_t> read_indices(const tinygltf::Model& model,
                                        const tinygltf::Primitive& primitive,
                                        std::size_t num_vertices,
                                        const std::filesystem::path& path) {
  std::vector<std::uint32_t> indices;
  for (double index : accessor_values(model, primitive.indices, path)) {
    if (!(index >= 0.0 && index < static_cast<double>(num_vertices))) {
      throw InputError(path.string(), "a vertex index is out of range");
    }
    indices.push_back(static_cast<std::uint32_t>(index));
  }
  return indices;
}

// A primitive's atlas: its encoded bytes, kept, and decoded.
void read_atlas(const tinygltf::Model& model,
                const tinygltf::Primitive& primitive,
                const std::filesystem::path& path,
                StoredModel& out) {
  const tinygltf::Material& material = model.materials.at(primitive.material);
  const tinygltf::Texture& texture = model.textures.at(material.pbrMetallicRoughness.baseColorTexture.index);
  const tinygltf::Image& image = model.images.at(texture.source);
  const tinygltf::BufferView& view = model.bufferViews.at(image.bufferView);
  const auto& data = model.buffers.at(view.buffer).data;
  if (view.byteOffset + view.byteLength > data.size()) {
    throw InputError(path.string(), "an atlas image reads past the end of its buffer");
  }
  EncodedImage encoded;
  encoded.bytes.assign(data.begin() + view.byteOffset, data.begin() + view.byteOffset + view.byteLength);
  encoded.mime_type = image.mimeType;
  encoded.extension = image.mimeType == "image/png" ? ".png" : ".jpg";
  cv::Mat decoded = cv::imdecode(encoded.bytes, cv::IMREAD_COLOR);
  if (decoded.empty()) throw InputError(path.string(), "an atlas image cannot be decoded");
  out.mesh.atlases.push_back(decoded);
  out.images.push_back(std::move(encoded));
}

}  // namespace

StoredModel read_glb_model(const std::filesystem::path& path) {
  const tinygltf::Model model = load_glb(path);
  for (const std::string& extension : model.extensionsRequired) {
    if (extension != "KHR_mesh_quantization") {
      throw InputError(path.string(), "it requires the glTF extension " + extension + ", which hos does not read");
    }
  }
  StoredModel out;
  if (model.meshes.empty() || model.meshes[0].primitives.empty()) return out;
  read_vertices(model, path, out.mesh);
  for (const tinygltf::Primitive& primitive : model.meshes[0].primitives) {
    read_atlas(model, primitive, path, out);
    out.mesh.indices.push_back(read_indices(model, primitive, out.mesh.positions.size(), path));
  }
  if (!model.nodes.empty() && model.nodes[0].matrix.size() == 16) {
    out.mesh.root_matrix = Eigen::Map<const Eigen::Matrix4d>(model.nodes[0].matrix.data());
  }
  read_placement_extras(model.asset.extras, out.mesh);
  return out;
}

std::filesystem::path preview_model_path(const std::filesystem::path& model) {
  return model.parent_path() / (model.stem().string() + ".preview.glb");
}

void convert_model(const std::filesystem::path& glb, const std::filesystem::path& target) {
  StoredModel model = read_glb_model(glb);
  write_model(target, model.mesh, model.images);
}

}  // namespace hos::texture
