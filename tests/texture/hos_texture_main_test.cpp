// The hos-texture executable: a workspace on disk in, a valid .glb out; exit
// codes for bad input and bad options.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/colmap_io.h"
#include "core/exit_codes.h"
#include "core/ply_io.h"
#include "synth/shapes.h"
#include "tests/support/test_support.h"
#include "tests/texture/scene_fixtures.h"
#include "texture/model_writer.h"

namespace hos::texture {
namespace {

namespace fs = std::filesystem;

void write_scene(const fs::path& root) {
  testing::write_sphere_workspace(root / "workspace", 6);
  write_mesh_ply(root / "mesh.ply", synth::icosphere(3, 1.0));
}

std::string texture_command(const fs::path& root, const std::string& extra = "") {
  return hos::testing::shell_quote((hos::testing::bin_dir() / "hos-texture").string()) + " --mesh " +
         hos::testing::shell_quote((root / "mesh.ply").string()) + " --workspace " +
         hos::testing::shell_quote((root / "workspace").string()) + " --output " +
         hos::testing::shell_quote((root / "model.glb").string()) + " --progress none " + extra;
}

TEST(HosTextureMain, WritesAGlbFromAWorkspace) {
  hos::testing::TempDir dir("hos-texture-main");
  write_scene(dir.path());
  const std::string report = (dir / "report.json").string();
  ASSERT_EQ(hos::testing::run_command(texture_command(dir.path(), "--image-format jpeg --atlas-size 1024 --report " +
                                                                      hos::testing::shell_quote(report)),
                                      dir / "log.txt"),
            kExitSuccess);
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &error, &warning, (dir / "model.glb").string())) << error;
  ASSERT_FALSE(model.images.empty());
  EXPECT_EQ(model.images[0].mimeType, "image/jpeg");
  EXPECT_LE(model.images[0].width, 1024);
  EXPECT_EQ(model.asset.generator, "hos");
  // The report's root matrix is the node's matrix.
  std::ifstream in(report);
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["faces"].get<int>(), 1280);
  EXPECT_EQ(j["views"].get<int>(), 6);
  ASSERT_EQ(model.nodes[0].matrix.size(), 16u);
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(j["root_matrix"][i].get<double>(), model.nodes[0].matrix[i], 1e-12);
}

// The atlas colour of a model at a vertex's UV.
cv::Vec3b colour_at(const TexturedMesh& mesh, std::size_t page, std::uint32_t v) {
  const cv::Mat& a = mesh.atlases[page];
  const int x = std::clamp(static_cast<int>(mesh.uvs[v].x() * a.cols), 0, a.cols - 1);
  const int y = std::clamp(static_cast<int>(mesh.uvs[v].y() * a.rows), 0, a.rows - 1);
  return a.at<cv::Vec3b>(y, x);
}

// Beside model.glb, model.preview.glb: at most preview_max_faces faces on
// one atlas of at most preview_atlas_size texels (the model's several pages
// scaled down into one), each preview vertex showing the colour the model
// shows at the same point; valid for the Khronos validator.
TEST(HosTextureMain, WritesAPreviewBesideTheModel) {
  hos::testing::TempDir dir("hos-texture-main");
  write_scene(dir.path());
  ASSERT_EQ(hos::testing::run_command(texture_command(dir.path(),
                                                      "--atlas-size 128 --set texture.preview_max_faces=400 "
                                                      "--set texture.preview_atlas_size=96"),
                                      dir / "log.txt"),
            kExitSuccess);
  const fs::path preview_path = dir / "model.preview.glb";
  ASSERT_TRUE(fs::exists(preview_path));
  const StoredModel full = read_glb_model(dir / "model.glb");
  const StoredModel preview = read_glb_model(preview_path);
  ASSERT_GT(full.mesh.atlases.size(), 1u);
  ASSERT_EQ(preview.mesh.atlases.size(), 1u);
  EXPECT_LE(std::max(preview.mesh.atlases[0].cols, preview.mesh.atlases[0].rows), 96);
  EXPECT_EQ(preview.images[0].mime_type, "image/jpeg");
  const std::size_t faces = preview.mesh.indices[0].size() / 3;
  std::cout << "[ figures  ] preview: " << faces << " faces, atlas " << preview.mesh.atlases[0].cols << "x"
            << preview.mesh.atlases[0].rows << "\n";
  EXPECT_LE(faces, 400u);
  EXPECT_GE(faces, 200u);
  for (int i = 0; i < 16; ++i) EXPECT_EQ(preview.mesh.root_matrix(i), full.mesh.root_matrix(i));
  // Every preview vertex is a model vertex (the same position up to the
  // preview's 16-bit grid: half a step of its bounding box's longest side /
  // 65535 per axis); its colour is the model's there, up to the scaling's
  // averaging and JPEG.
  Eigen::Vector3f lo = preview.mesh.positions[0], hi = lo;
  for (const auto& p : preview.mesh.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const float tolerance = 0.5f * (hi - lo).maxCoeff() / 65535.0f * 1.01f + 1e-6f;
  double error = 0.0;
  std::size_t count = 0;
  for (std::uint32_t v : preview.mesh.indices[0]) {
    const Eigen::Vector3f& p = preview.mesh.positions[v];
    float best = 1e30f;
    std::pair<std::size_t, std::uint32_t> nearest;
    for (std::size_t page = 0; page < full.mesh.indices.size(); ++page) {
      for (std::uint32_t w : full.mesh.indices[page]) {
        const float d = (full.mesh.positions[w] - p).cwiseAbs().maxCoeff();
        if (d < best) best = d, nearest = {page, w};
      }
    }
    ASSERT_LE(best, tolerance);
    const cv::Vec3b a = colour_at(preview.mesh, 0, v), b = colour_at(full.mesh, nearest.first, nearest.second);
    error += cv::norm(cv::Vec3d(a) - cv::Vec3d(b));
    ++count;
  }
  std::cout << "[ figures  ] preview: mean colour difference at the vertices " << error / count << "\n";
  EXPECT_LT(error / count, 25.0);
  const fs::path modules = hos::testing::bin_dir().parent_path() / "node_tools" / "node_modules";
  if (!fs::exists(modules / "gltf-validator")) GTEST_SKIP() << "gltf-validator is installed by GltfWriter tests";
  const fs::path script = hos::testing::source_dir() / "tests" / "texture" / "validate_gltf.js";
  const int status = hos::testing::run_command("node " + hos::testing::shell_quote(script.string()) + " " +
                                                   hos::testing::shell_quote(modules.string()) + " " +
                                                   hos::testing::shell_quote(preview_path.string()),
                                               dir / "validator.json");
  EXPECT_EQ(status, 0) << hos::testing::read_text(dir / "validator.json");
}

TEST(HosTextureMain, NoPreviewWhenItsFaceBudgetIsZero) {
  hos::testing::TempDir dir("hos-texture-main");
  write_scene(dir.path());
  ASSERT_EQ(
      hos::testing::run_command(texture_command(dir.path(), "--set texture.preview_max_faces=0"), dir / "log.txt"),
      kExitSuccess);
  EXPECT_TRUE(fs::exists(dir / "model.glb"));
  EXPECT_FALSE(fs::exists(dir / "model.preview.glb"));
}

TEST(HosTextureMain, MissingMeshIsBadInput) {
  hos::testing::TempDir dir("hos-texture-main");
  write_scene(dir.path());
  fs::remove(dir / "mesh.ply");
  EXPECT_EQ(hos::testing::run_command(texture_command(dir.path()), dir / "log.txt"), kExitBadInput);
  EXPECT_FALSE(fs::exists(dir / "model.glb"));
}

TEST(HosTextureMain, BadOptionIsUsageError) {
  hos::testing::TempDir dir("hos-texture-main");
  write_scene(dir.path());
  EXPECT_EQ(hos::testing::run_command(texture_command(dir.path(), "--set texture.atlas_size=5"), dir / "log.txt"),
            kExitUsage);
  EXPECT_EQ(hos::testing::run_command(texture_command(dir.path(), "--set texture.no_such_key=1"), dir / "log.txt"),
            kExitUsage);
}

}  // namespace
}  // namespace hos::texture
