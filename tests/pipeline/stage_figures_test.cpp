#include "pipeline/stage_figures.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "tests/support/test_support.h"

namespace hos::pipeline {
namespace {
namespace fs = std::filesystem;

void append32(std::string& s, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) s += static_cast<char>((v >> (8 * i)) & 0xFF);
}

TEST(StageFigures, PlyElementCounts) {
  hos::testing::TempDir dir;
  std::ofstream(dir / "m.ply")
      << "ply\nformat binary_little_endian 1.0\ncomment x\nelement vertex 12\n"
         "property float x\nelement face 7\nproperty list uchar int vertex_indices\nend_header\n";
  const auto counts = ply_element_counts(dir / "m.ply");
  EXPECT_EQ(counts.at("vertex"), 12);
  EXPECT_EQ(counts.at("face"), 7);
  std::ofstream(dir / "bad.ply") << "not a ply\n";
  EXPECT_THROW(ply_element_counts(dir / "bad.ply"), InputError);
  EXPECT_THROW(ply_element_counts(dir / "missing.ply"), InputError);
}

TEST(StageFigures, GlbMeshAndTextureSizes) {
  // A hand-made glb: one primitive with 5 positions and 9 indices, one 40x30 PNG.
  std::vector<std::uint8_t> png;
  cv::imencode(".png", cv::Mat(30, 40, CV_8UC3, cv::Scalar(1, 2, 3)), png);
  const std::string json =
      R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)"
      R"("accessors":[{"count":5},{"count":9}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":)" +
      std::to_string(png.size()) + R"(}],"images":[{"bufferView":0,"mimeType":"image/png"}]})";
  std::string padded_json = json;
  while (padded_json.size() % 4) padded_json += ' ';
  std::string bin(png.begin(), png.end());
  while (bin.size() % 4) bin += '\0';
  std::string glb = "glTF";
  append32(glb, 2);
  append32(glb, static_cast<std::uint32_t>(12 + 8 + padded_json.size() + 8 + bin.size()));
  append32(glb, static_cast<std::uint32_t>(padded_json.size()));
  glb += "JSON" + padded_json;
  append32(glb, static_cast<std::uint32_t>(bin.size()));
  glb += std::string("BIN\0", 4) + bin;
  hos::testing::TempDir dir;
  std::ofstream(dir / "m.glb", std::ios::binary) << glb;
  const GlbFigures f = read_glb_figures(dir / "m.glb");
  EXPECT_EQ(f.bytes, static_cast<std::int64_t>(glb.size()));
  EXPECT_EQ(f.vertices, 5);
  EXPECT_EQ(f.triangles, 3);
  ASSERT_EQ(f.texture_sizes.size(), 1u);
  EXPECT_EQ(f.texture_sizes[0], std::make_pair(40, 30));
  std::ofstream(dir / "x.glb") << "nope";
  EXPECT_THROW(read_glb_figures(dir / "x.glb"), InputError);
}

TEST(StageFigures, SfmStepTimesReachTheSummary) {
  hos::testing::TempDir dir;
  fs::create_directories(dir / "sfm");
  std::ofstream(dir / "sfm" / "report.json")
      << R"({"images_given": 11, "images_registered": 10, "points": 5000, "matcher": "vocab_tree",)"
      << R"( "step_seconds": {"feature_extractor": 12.25, "vocab_tree_builder": 2.0, "mapper": 8.0}})";
  const auto figures = stage_figures("sfm", dir.path());
  EXPECT_EQ(figures["step_seconds"].size(), 3u);
  EXPECT_EQ(figures_text("sfm", figures),
            "10/11 images registered, 5000 points, vocab_tree matching; feature_extractor 12.2 s; "
            "vocab_tree_builder 2.0 s; mapper 8.0 s");
}

// Debris and unseen faces reach the summary from the stages' report.json.
TEST(StageFigures, DebrisAndUnseenFacesReachTheSummary) {
  hos::testing::TempDir dir;
  fs::create_directories(dir / "recon");
  std::ofstream(dir / "recon" / "mesh.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                               "property float y\nproperty float z\nelement face 1\n"
                                               "property list uchar int vertex_indices\nend_header\n"
                                               "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  std::ofstream(dir / "recon" / "report.json")
      << R"({"faces": 1, "debris_pieces_removed": 3, "debris_area_removed": 0.5, "surface_area": 99.5})";
  EXPECT_EQ(figures_text("recon", stage_figures("recon", dir.path())),
            "3 vertices, 1 faces; 3 debris pieces removed (0.5% of the area)");
  fs::create_directories(dir / "texture");
  std::ofstream(dir / "texture" / "report.json") << R"({"unseen_faces": 42})";
  const auto texture = stage_figures("texture", dir.path());
  EXPECT_EQ(texture["unseen_faces"], 42);
}

}  // namespace
}  // namespace hos::pipeline
