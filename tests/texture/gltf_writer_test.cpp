#include "texture/gltf_writer.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <Eigen/Core>
#include <cstring>

#include "core/error.h"
#include "synth/shapes.h"
#include "tests/support/test_support.h"
#include "tests/texture/scene_fixtures.h"
#include "texture/model_writer.h"
#include "texture/texture_mesh.h"

namespace hos::texture {
namespace {

namespace fs = std::filesystem;

TexturedMesh textured_sphere(int atlas_size = 4096) {
  const TriangleMesh mesh = synth::icosphere(3, 1.0);
  std::vector<TextureView> views;
  for (int i = 0; i < 6; ++i) {
    views.push_back(testing::make_view(testing::view_name(i), 60.0 * i, 10.0, 3.5));
    testing::render_sphere(views.back(), 1.0);
  }
  TextureOptions options;
  options.atlas_size = atlas_size;
  return texture_mesh(mesh, views, options, null_reporter()).mesh;
}

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

// KHR_mesh_quantization: the validator reads the quantized accessors (it
// checks their bounds and that the extension is declared), and the
// positions, dequantized by the node matrices, come back within half a step
// of the longest side / 65535; UVs (clamped to [0, 1]) within half of 1/65535.
TEST(GltfWriter, QuantizedMeshPassesKhronosValidatorAndDequantizes) {
  hos::testing::TempDir dir("hos-texture-gltf");
  TexturedMesh mesh = textured_sphere();
  mesh.root_matrix(1, 3) = 2.5;
  GltfWriteOptions options;
  options.mesh_compression = "quantized";
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
    EXPECT_EQ(status, 0) << name << ": " << text;
    EXPECT_NE(text.find("\"numErrors\": 0"), std::string::npos) << text;
    EXPECT_NE(text.find("KHR_mesh_quantization"), std::string::npos) << text;
  }
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
  // A compressed model cannot be converted: it says so.
  EXPECT_THROW(read_glb_model(dir / "model.glb"), InputError);
}

TEST(GltfWriter, UnwritableTargetThrowsOutputError) {
  EXPECT_THROW(write_glb("/nonexistent-folder/x/model.glb", textured_sphere()), Error);
}

}  // namespace
}  // namespace hos::texture
