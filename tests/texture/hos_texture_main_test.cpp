// The hos-texture executable: a workspace on disk in, a valid .glb out; exit
// codes for bad input and bad options.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/colmap_io.h"
#include "core/exit_codes.h"
#include "core/ply_io.h"
#include "synth/shapes.h"
#include "tests/support/test_support.h"
#include "tests/texture/scene_fixtures.h"

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
