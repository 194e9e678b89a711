#include "texture/model_writer.h"

#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"

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

// The floats (or uint32 indices) of an accessor this project's writer made.
template <typename T>
std::vector<T> accessor_values(const tinygltf::Model& model, int index, const std::filesystem::path& path) {
  if (index < 0 || index >= static_cast<int>(model.accessors.size())) {
    throw InputError(path.string(), "a primitive refers to a missing accessor");
  }
  const tinygltf::Accessor& a = model.accessors[index];
  const tinygltf::BufferView& view = model.bufferViews.at(a.bufferView);
  const auto& data = model.buffers.at(view.buffer).data;
  const std::size_t count = a.count * static_cast<std::size_t>(tinygltf::GetNumComponentsInType(a.type));
  const std::size_t start = view.byteOffset + a.byteOffset;
  if ((view.byteStride != 0 && view.byteStride != tinygltf::GetNumComponentsInType(a.type) * sizeof(T)) ||
      tinygltf::GetComponentSizeInBytes(a.componentType) != static_cast<int>(sizeof(T)) ||
      start + count * sizeof(T) > data.size()) {
    throw InputError(path.string(), "an accessor is not in the layout hos writes");
  }
  std::vector<T> values(count);
  std::memcpy(values.data(), data.data() + start, count * sizeof(T));
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

}  // namespace

StoredModel read_glb_model(const std::filesystem::path& path) {
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  // The images stay encoded here; they are decoded once below.
  loader.SetImageLoader([](tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                           void*) { return true; },
                        nullptr);
  std::string error, warning;
  if (!loader.LoadBinaryFromFile(&model, &error, &warning, path.string())) {
    throw InputError(path.string(), "not a readable binary glTF: " + error);
  }
  if (!model.extensionsRequired.empty()) {
    throw InputError(path.string(), "its mesh is compressed (" + model.extensionsRequired[0] +
                                        "); write it with texture.mesh_compression none to convert it");
  }
  StoredModel out;
  if (model.meshes.empty() || model.meshes[0].primitives.empty()) return out;
  const auto& primitives = model.meshes[0].primitives;
  const auto& attributes = primitives[0].attributes;
  if (!attributes.count("POSITION") || !attributes.count("NORMAL") || !attributes.count("TEXCOORD_0")) {
    throw InputError(path.string(), "the mesh lacks positions, normals or texture coordinates");
  }
  const std::vector<float> p = accessor_values<float>(model, attributes.at("POSITION"), path);
  const std::vector<float> n = accessor_values<float>(model, attributes.at("NORMAL"), path);
  const std::vector<float> t = accessor_values<float>(model, attributes.at("TEXCOORD_0"), path);
  for (std::size_t i = 0; i + 2 < p.size() && i + 2 < n.size(); i += 3) {
    out.mesh.positions.emplace_back(p[i], p[i + 1], p[i + 2]);
    out.mesh.normals.emplace_back(n[i], n[i + 1], n[i + 2]);
  }
  for (std::size_t i = 0; i + 1 < t.size(); i += 2) out.mesh.uvs.emplace_back(t[i], t[i + 1]);
  for (const tinygltf::Primitive& primitive : primitives) {
    const tinygltf::Material& material = model.materials.at(primitive.material);
    const tinygltf::Texture& texture = model.textures.at(material.pbrMetallicRoughness.baseColorTexture.index);
    const tinygltf::Image& image = model.images.at(texture.source);
    const tinygltf::BufferView& view = model.bufferViews.at(image.bufferView);
    const auto& data = model.buffers.at(view.buffer).data;
    EncodedImage encoded;
    encoded.bytes.assign(data.begin() + view.byteOffset, data.begin() + view.byteOffset + view.byteLength);
    encoded.mime_type = image.mimeType;
    encoded.extension = image.mimeType == "image/png" ? ".png" : ".jpg";
    cv::Mat decoded = cv::imdecode(encoded.bytes, cv::IMREAD_COLOR);
    if (decoded.empty()) throw InputError(path.string(), "an atlas image cannot be decoded");
    out.mesh.atlases.push_back(decoded);
    out.images.push_back(std::move(encoded));
    out.mesh.indices.push_back(accessor_values<std::uint32_t>(model, primitive.indices, path));
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
