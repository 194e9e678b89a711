#include "texture/gltf_writer.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <iostream>

#include "core/error.h"
#include "tests/support/test_support.h"
#include "tests/texture/scene_fixtures.h"
#include "texture/model_writer.h"

namespace hos::texture {
namespace {

namespace fs = std::filesystem;
using testing::textured_sphere;

// The validator's node_modules folder: installed once per build folder.
fs::path validator_modules() {
  const fs::path prefix = hos::testing::bin_dir().parent_path() / "node_tools";
  fs::path modules = prefix / "node_modules";
  if (!fs::exists(modules / "gltf-validator" / "package.json")) {
    const int status = hos::testing::run_command(
        "npm install --no-audit --no-fund --prefix " + hos::testing::shell_quote(prefix.string()) + " gltf-validator",
        prefix.parent_path() / "node_tools_install.log");
    if (status != 0) return {};
  }
  return modules;
}

TEST(GltfWriter, GlbPassesKhronosValidator) {
  hos::testing::TempDir dir("hos-texture-gltf");
  const fs::path glb = dir / "model.glb";
  // PNG, JPEG, and several atlas pages (primitives).
  for (const std::string format : {"png", "jpeg", "pages"}) {
    GltfWriteOptions options;
    options.image_format = format == "jpeg" ? "jpeg" : "png";
    const TexturedMesh mesh = textured_sphere(format == "pages" ? 128 : 4096);
    if (format == "pages") {
      ASSERT_GT(mesh.atlases.size(), 1u);
    }
    write_glb(glb, mesh, options);
    const fs::path modules = validator_modules();
    ASSERT_FALSE(modules.empty()) << "npm install gltf-validator failed";
    const fs::path script = hos::testing::source_dir() / "tests" / "texture" / "validate_gltf.js";
    const fs::path report = dir / ("report_" + format + ".json");
    const int status = hos::testing::run_command("node " + hos::testing::shell_quote(script.string()) + " " +
                                                     hos::testing::shell_quote(modules.string()) + " " +
                                                     hos::testing::shell_quote(glb.string()),
                                                 report);
    const std::string text = hos::testing::read_text(report);
    EXPECT_EQ(status, 0) << format << ": " << text;
    EXPECT_NE(text.find("\"numErrors\": 0"), std::string::npos) << text;
  }
}

TEST(GltfWriter, ReadsBackWithTinyGltf) {
  hos::testing::TempDir dir("hos-texture-gltf");
  TexturedMesh mesh = textured_sphere();
  mesh.root_matrix(1, 3) = 2.5;  // a translation, to check the matrix layout
  const fs::path glb = dir / "model.glb";
  write_glb(glb, mesh);
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &error, &warning, glb.string())) << error;
  EXPECT_EQ(model.asset.generator, "hos");
  ASSERT_EQ(model.nodes.size(), 1u);
  ASSERT_EQ(model.nodes[0].matrix.size(), 16u);
  EXPECT_DOUBLE_EQ(model.nodes[0].matrix[13], 2.5);  // column-major: column 3, row 1
  ASSERT_EQ(model.meshes.size(), 1u);
  std::size_t triangles = 0;
  for (const auto& primitive : model.meshes[0].primitives) {
    EXPECT_EQ(primitive.attributes.count("TEXCOORD_0"), 1u);
    EXPECT_EQ(primitive.attributes.count("NORMAL"), 1u);
    triangles += model.accessors[primitive.indices].count / 3;
    const auto& material = model.materials[primitive.material];
    EXPECT_EQ(material.pbrMetallicRoughness.metallicFactor, 0.0);
    EXPECT_EQ(material.pbrMetallicRoughness.roughnessFactor, 1.0);
    const int image = model.textures[material.pbrMetallicRoughness.baseColorTexture.index].source;
    EXPECT_EQ(model.images[image].mimeType, "image/jpeg");  // the default
    EXPECT_EQ(model.images[image].width, mesh.atlases[0].cols);
  }
  std::size_t expected = 0;
  for (const auto& idx : mesh.indices) expected += idx.size() / 3;
  EXPECT_EQ(triangles, expected);
  EXPECT_EQ(model.accessors[model.meshes[0].primitives[0].attributes["POSITION"]].count, mesh.positions.size());
}

// The Khronos validator's report of a file (status 0: no errors).
int validate(const fs::path& file, const fs::path& report) {
  const fs::path modules = validator_modules();
  if (modules.empty()) return -1;
  const fs::path script = hos::testing::source_dir() / "tests" / "texture" / "validate_gltf.js";
  return hos::testing::run_command("node " + hos::testing::shell_quote(script.string()) + " " +
                                       hos::testing::shell_quote(modules.string()) + " " +
                                       hos::testing::shell_quote(file.string()),
                                   report);
}

// KHR_mesh_quantization and EXT_meshopt_compression, .glb and .gltf: the
// validator reads the quantized accessors (it checks their bounds and that
// the extensions are declared) and decodes the meshopt streams.
TEST(GltfWriter, CompressedMeshesPassKhronosValidator) {
  hos::testing::TempDir dir("hos-texture-gltf");
  TexturedMesh mesh = textured_sphere(128);  // several pages: primitives
  ASSERT_GT(mesh.atlases.size(), 1u);
  mesh.root_matrix(1, 3) = 2.5;
  for (const std::string compression : {"quantized", "meshopt"}) {
    GltfWriteOptions options;
    options.mesh_compression = compression;
    for (const std::string name : {"model.glb", "model.gltf"}) {
      const fs::path file = dir / name;
      if (name == "model.glb") {
        write_glb(file, mesh, options);
      } else {
        write_gltf(file, mesh, encode_atlases(mesh, options, file), options.mesh_compression);
      }
      const int status = validate(file, dir / "report.json");
      ASSERT_NE(status, -1) << "npm install gltf-validator failed";
      const std::string text = hos::testing::read_text(dir / "report.json");
      EXPECT_EQ(status, 0) << compression << " " << name << ": " << text;
      EXPECT_NE(text.find("\"numErrors\": 0"), std::string::npos) << text;
      EXPECT_NE(text.find("KHR_mesh_quantization"), std::string::npos) << text;
      if (compression == "meshopt") {
        EXPECT_NE(text.find("EXT_meshopt_compression"), std::string::npos) << text;
      }
    }
  }
}

// The quantized file's own bytes (read by tinygltf, no decoder of ours): the
// positions, dequantized by the node matrices, come back within half a step
// of the longest side / 65535; UVs (clamped to [0, 1]) within half of 1/65535.
TEST(GltfWriter, QuantizedMeshDequantizesByItsNodeMatrix) {
  hos::testing::TempDir dir("hos-texture-gltf");
  TexturedMesh mesh = textured_sphere();
  mesh.root_matrix(1, 3) = 2.5;
  GltfWriteOptions options;
  options.mesh_compression = "quantized";
  write_glb(dir / "model.glb", mesh, options);
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &error, &warning, (dir / "model.glb").string())) << error;
  ASSERT_EQ(model.nodes.size(), 2u);
  EXPECT_DOUBLE_EQ(model.nodes[0].matrix[13], 2.5);
  ASSERT_EQ(model.nodes[0].children, std::vector<int>{1});
  const Eigen::Matrix4d dequantize = Eigen::Map<const Eigen::Matrix4d>(model.nodes[1].matrix.data());
  const auto& attributes = model.meshes[0].primitives[0].attributes;
  const tinygltf::Accessor& positions = model.accessors[attributes.at("POSITION")];
  const tinygltf::Accessor& uvs = model.accessors[attributes.at("TEXCOORD_0")];
  ASSERT_EQ(positions.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
  ASSERT_EQ(positions.count, mesh.positions.size());
  const tinygltf::BufferView& pview = model.bufferViews[positions.bufferView];
  const tinygltf::BufferView& tview = model.bufferViews[uvs.bufferView];
  const auto& data = model.buffers[0].data;
  const double step = dequantize(0, 0);
  double worst = 0.0, worst_uv = 0.0;
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    std::uint16_t q[3], t[2];
    std::memcpy(q, data.data() + pview.byteOffset + i * pview.byteStride, sizeof q);
    std::memcpy(t, data.data() + tview.byteOffset + i * 4, sizeof t);
    const Eigen::Vector4d p = dequantize * Eigen::Vector4d(q[0], q[1], q[2], 1.0);
    worst = std::max(worst, (p.head<3>() - mesh.positions[i].cast<double>()).cwiseAbs().maxCoeff());
    // A chart vertex on a page's edge may lie up to a texel outside [0, 1]
    // (texel centres decide what a chart covers): such UVs are clamped.
    for (int k = 0; k < 2; ++k) {
      worst_uv = std::max(worst_uv, std::abs(t[k] / 65535.0 - std::clamp(mesh.uvs[i][k], 0.0f, 1.0f)));
    }
  }
  EXPECT_LE(worst, 0.5 * step * 1.0001);
  EXPECT_LE(worst_uv, 0.5 / 65535.0 + 1e-7);
  EXPECT_GT(step, 0.0);
}

// Each vertex's first copy (same position and UV; unseen faces share a
// texel, so such copies exist).
std::vector<std::size_t> first_copies(const TexturedMesh& mesh) {
  std::vector<std::size_t> first(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    first[v] = v;
    for (std::size_t w = 0; w < v; ++w) {
      if (mesh.positions[w] == mesh.positions[v] && mesh.uvs[w] == mesh.uvs[v]) {
        first[v] = w;
        break;
      }
    }
  }
  return first;
}

// The original vertex each read-back vertex stands for: the nearest in
// position (relative to extent) plus UV, as its first copy; the writer may
// reorder vertices.
std::vector<std::size_t> nearest_vertices(const TexturedMesh& original, const TexturedMesh& read, double extent) {
  const std::vector<std::size_t> first = first_copies(original);
  std::vector<std::size_t> nearest;
  for (std::size_t i = 0; i < read.positions.size(); ++i) {
    double best = 1e300;
    std::size_t best_v = 0;
    for (std::size_t v = 0; v < original.positions.size(); ++v) {
      const Eigen::Vector2f uv = original.uvs[v].cwiseMax(0.0f).cwiseMin(1.0f);
      const double d = (original.positions[v] - read.positions[i]).cwiseAbs().maxCoeff() / extent +
                       (uv - read.uvs[i]).cwiseAbs().maxCoeff();
      if (d < best) best = d, best_v = v;
    }
    nearest.push_back(first[best_v]);
  }
  return nearest;
}

// A page's triangles as sorted vertex triples, each rotated to start at its
// smallest vertex (the meshopt index codec may rotate triangles).
std::vector<std::array<std::size_t, 3>> triangle_set(const std::vector<std::uint32_t>& indices,
                                                     const std::vector<std::size_t>& vertex_of) {
  std::vector<std::array<std::size_t, 3>> out;
  for (std::size_t k = 0; k + 2 < indices.size(); k += 3) {
    std::array<std::size_t, 3> t = {vertex_of[indices[k]], vertex_of[indices[k + 1]], vertex_of[indices[k + 2]]};
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    out.push_back(t);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Each mesh_compression written and read back with read_glb_model (which
// decodes the meshopt streams with meshoptimizer and dequantizes): the same
// triangles on the same pages (vertices told apart by position and UV), the same atlas bytes and root matrix;
// positions within half a grid step (bounding box's longest side / 65535)
// per axis, UVs (clamped to [0, 1]) within half of 1/65535, unit normals
// within sqrt(3) / 127 (half an 8-bit step per component, renormalized);
// none: floats exactly (normals as the writer normalizes them).
TEST(GltfWriter, EachCompressionReadsBackWithinItsBounds) {
  hos::testing::TempDir dir("hos-texture-gltf");
  TexturedMesh mesh = textured_sphere(128);
  ASSERT_GT(mesh.atlases.size(), 1u);
  mesh.root_matrix(0, 3) = -1.5;
  Eigen::Vector3f lo = mesh.positions[0], hi = mesh.positions[0];
  for (const auto& p : mesh.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double extent = (hi - lo).maxCoeff();
  for (const std::string compression : {"none", "quantized", "meshopt"}) {
    GltfWriteOptions options;
    options.mesh_compression = compression;
    const fs::path file = dir / (compression + ".glb");
    write_glb(file, mesh, options);
    const StoredModel read = read_glb_model(file);
    const bool exact = compression == "none";
    const double position_bound = exact ? 0.0 : 0.5 * extent / 65535.0 * 1.0001 + 1e-6;
    const double uv_bound = exact ? 0.0 : 0.5 / 65535.0 + 1e-7;
    const double normal_bound = exact ? 1e-6 : std::sqrt(3.0) / 127.0;
    const std::vector<std::size_t> original = nearest_vertices(mesh, read.mesh, extent);
    double worst_position = 0.0, worst_uv = 0.0, worst_normal = 0.0;
    for (std::size_t i = 0; i < original.size(); ++i) {
      const std::size_t v = original[i];
      const Eigen::Vector2f uv = exact ? mesh.uvs[v] : Eigen::Vector2f(mesh.uvs[v].cwiseMax(0.0f).cwiseMin(1.0f));
      worst_position =
          std::max(worst_position, double((read.mesh.positions[i] - mesh.positions[v]).cwiseAbs().maxCoeff()));
      worst_uv = std::max(worst_uv, double((read.mesh.uvs[i] - uv).cwiseAbs().maxCoeff()));
      worst_normal = std::max(worst_normal, double((read.mesh.normals[i] - mesh.normals[v].normalized()).norm()));
    }
    std::cout << "[ figures  ] " << compression << ": " << fs::file_size(file) << " bytes, worst position "
              << worst_position << " (bound " << position_bound << "), uv " << worst_uv << ", normal " << worst_normal
              << "\n";
    EXPECT_LE(worst_position, position_bound) << compression;
    EXPECT_LE(worst_uv, uv_bound) << compression;
    EXPECT_LE(worst_normal, normal_bound) << compression;
    ASSERT_EQ(read.mesh.indices.size(), mesh.indices.size()) << compression;
    const std::vector<std::size_t> first = first_copies(mesh);
    for (std::size_t page = 0; page < mesh.indices.size(); ++page) {
      EXPECT_EQ(triangle_set(read.mesh.indices[page], original), triangle_set(mesh.indices[page], first))
          << compression << " page " << page;
      EXPECT_EQ(read.images[page].bytes, encode_atlases(mesh, options, file)[page].bytes);
    }
    for (int k = 0; k < 16; ++k) EXPECT_EQ(read.mesh.root_matrix(k), mesh.root_matrix(k)) << compression;
  }
  // meshopt compresses this sphere's geometry below the quantized file's.
  EXPECT_LT(fs::file_size(dir / "meshopt.glb"), fs::file_size(dir / "quantized.glb"));
  EXPECT_LT(fs::file_size(dir / "quantized.glb"), fs::file_size(dir / "none.glb"));
}

// A meshopt .glb cut short is an InputError naming the file, for the model
// reader as for any other.
TEST(GltfWriter, TruncatedMeshoptFileIsBadInput) {
  hos::testing::TempDir dir("hos-texture-gltf");
  GltfWriteOptions options;
  options.mesh_compression = "meshopt";
  const fs::path file = dir / "model.glb";
  write_glb(file, textured_sphere(), options);
  fs::resize_file(file, fs::file_size(file) / 2);
  try {
    read_glb_model(file);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("model.glb"), std::string::npos) << e.what();
  }
}

TEST(GltfWriter, UnwritableTargetThrowsOutputError) {
  EXPECT_THROW(write_glb("/nonexistent-folder/x/model.glb", textured_sphere()), Error);
}

}  // namespace
}  // namespace hos::texture
