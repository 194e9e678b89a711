// core/ply_io.*: round trips in all three formats and every bad-input case.
#include "core/ply_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "core/error.h"
#include "tests/support/test_support.h"

namespace hos {
namespace {

PointCloud cloud() {
  PointCloud c;
  for (int i = 0; i < 50; ++i) {
    c.positions.emplace_back(0.1f * i, -0.2f * i, 1.5f + i);
    c.normals.push_back(Eigen::Vector3f(i, 1, 2).normalized());
    c.colors.push_back({static_cast<std::uint8_t>(i), 100, static_cast<std::uint8_t>(255 - i)});
    c.confidence.push_back(0.5f * i);
  }
  c.scalars["intensity"] = std::vector<float>(50, 7.25f);
  return c;
}

class PlyFormats : public ::testing::TestWithParam<PlyFormat> {};

TEST_P(PlyFormats, PointCloudRoundTrip) {
  hos::testing::TempDir dir;
  const PointCloud a = cloud();
  write_point_cloud_ply(dir / "p.ply", a, GetParam());
  const PointCloud b = read_point_cloud_ply(dir / "p.ply");
  ASSERT_EQ(b.size(), a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_TRUE(a.positions[i].isApprox(b.positions[i], 1e-6f));
    EXPECT_TRUE(a.normals[i].isApprox(b.normals[i], 1e-6f));
    EXPECT_EQ(a.colors[i], b.colors[i]);
    EXPECT_FLOAT_EQ(a.confidence[i], b.confidence[i]);
  }
  ASSERT_EQ(b.scalars.count("intensity"), 1u);
  EXPECT_FLOAT_EQ(b.scalars.at("intensity")[3], 7.25f);
}

TEST_P(PlyFormats, MeshRoundTrip) {
  hos::testing::TempDir dir;
  TriangleMesh a;
  a.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  a.colors = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}, {10, 11, 12}};
  a.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  write_mesh_ply(dir / "m.ply", a, GetParam());
  const TriangleMesh b = read_mesh_ply(dir / "m.ply");
  ASSERT_EQ(b.num_vertices(), 4u);
  ASSERT_EQ(b.num_faces(), 4u);
  for (std::size_t f = 0; f < 4; ++f) EXPECT_EQ(a.faces[f], b.faces[f]);
  EXPECT_EQ(b.colors[3], a.colors[3]);
}

INSTANTIATE_TEST_SUITE_P(AllFormats,
                         PlyFormats,
                         ::testing::Values(PlyFormat::kAscii,
                                           PlyFormat::kBinaryLittleEndian,
                                           PlyFormat::kBinaryBigEndian));

std::string error_of(const std::filesystem::path& path) {
  return hos::testing::input_error_of([&] { read_point_cloud_ply(path); });
}

TEST(PlyIo, BadInputsAreInputErrorsNamingTheFile) {
  hos::testing::TempDir dir;
  EXPECT_NE(error_of(dir / "missing.ply").find("missing.ply"), std::string::npos);

  std::ofstream(dir / "magic.ply") << "not a ply\n";
  EXPECT_NE(error_of(dir / "magic.ply").find("magic.ply"), std::string::npos);

  std::ofstream(dir / "truncated_header.ply") << "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n";
  EXPECT_NE(error_of(dir / "truncated_header.ply").find("end_header"), std::string::npos);

  std::ofstream(dir / "bad_type.ply") << "ply\nformat ascii 1.0\nelement vertex 1\nproperty quux x\nend_header\n1\n";
  EXPECT_NE(error_of(dir / "bad_type.ply").find("quux"), std::string::npos);

  std::ofstream(dir / "short.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                      "property float z\nend_header\n1 2 3\n4 5 6\n";
  EXPECT_NE(error_of(dir / "short.ply").find("truncated"), std::string::npos);

  std::ofstream(dir / "long.ply") << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                     "property float z\nend_header\n1 2 3\n4 5 6\n";
  EXPECT_NE(error_of(dir / "long.ply").find("more data"), std::string::npos);

  // Binary data shorter than the header's count.
  write_point_cloud_ply(dir / "bin.ply", cloud(), PlyFormat::kBinaryLittleEndian);
  std::filesystem::resize_file(dir / "bin.ply", std::filesystem::file_size(dir / "bin.ply") - 10);
  EXPECT_NE(error_of(dir / "bin.ply").find("truncated"), std::string::npos);

  // A count no data could hold is refused before anything is allocated for it.
  std::ofstream(dir / "huge.ply", std::ios::binary)
      << "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\n"
         "property float y\nproperty float z\nend_header\n0123456789ab";
  EXPECT_NE(error_of(dir / "huge.ply").find("truncated"), std::string::npos);

  // A property named twice (a fuzzed header had nx twice and no ny) would fill
  // one attribute twice; an element named twice is as ambiguous.
  std::ofstream(dir / "twice.ply") << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                      "property float z\nproperty float nx\nproperty float nx\nproperty float nz\n"
                                      "end_header\n1 2 3 0 0 1\n";
  EXPECT_NE(error_of(dir / "twice.ply").find("'nx' appears twice"), std::string::npos);
  std::ofstream(dir / "two_elements.ply") << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                             "element vertex 1\nproperty float y\nend_header\n1\n2\n";
  EXPECT_NE(error_of(dir / "two_elements.ply").find("'vertex' appears twice"), std::string::npos);
}

TEST(PlyIo, NonFiniteCoordinatesAreSkippedAndCounted) {
  hos::testing::TempDir dir;
  std::ofstream(dir / "nan.ply") << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                                    "property float z\nend_header\n1 2 3\nnan 0 0\n4 inf 6\n7 8 9\n";
  PlyReadReport report;
  const PointCloud c = read_point_cloud_ply(dir / "nan.ply", &report);
  EXPECT_EQ(c.size(), 2u);
  EXPECT_EQ(report.num_skipped_nonfinite, 2u);
  for (const auto& p : c.positions) EXPECT_TRUE(p.allFinite());
  // A mesh cannot drop vertices (faces would dangle): an error.
  EXPECT_THROW(read_mesh_ply(dir / "nan.ply"), InputError);

  // Binary rows are decoded in parallel and compacted afterwards: the kept
  // points keep their order and their own normals and colours.
  PointCloud in;
  for (int i = 0; i < 1000; ++i) {
    const float v = static_cast<float>(i);
    in.positions.emplace_back(i % 7 == 3 ? std::nanf("") : v, v, v);
    in.normals.emplace_back(0.0f, 0.0f, v);
    in.colors.push_back({static_cast<std::uint8_t>(i % 256), 0, 0});
  }
  write_point_cloud_ply(dir / "nan.bin.ply", in, PlyFormat::kBinaryLittleEndian);
  const PointCloud b = read_point_cloud_ply(dir / "nan.bin.ply", &report);
  EXPECT_EQ(report.num_skipped_nonfinite, 143u);  // i % 7 == 3 for i < 1000
  ASSERT_EQ(b.size(), 1000u - 143u);
  ASSERT_EQ(b.normals.size(), b.size());
  ASSERT_EQ(b.colors.size(), b.size());
  for (std::size_t k = 0; k < b.size(); ++k) {
    const int i = static_cast<int>(b.positions[k].y());
    ASSERT_NE(i % 7, 3);
    if (k > 0) {
      EXPECT_GT(b.positions[k].y(), b.positions[k - 1].y());
    }
    EXPECT_EQ(b.normals[k].z(), static_cast<float>(i));
    EXPECT_EQ(b.colors[k][0], i % 256);
  }
}

TEST(PlyIo, UnusableConfidencesReadAsZeroAndCounted) {
  testing::TempDir dir;
  std::ofstream(dir / "conf.ply") << "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                                     "property float z\nproperty float confidence\nend_header\n"
                                     "0 0 0 nan\n1 0 0 -1\n0 1 0 inf\n0 0 1 2\n";
  PlyReadReport report;
  const PointCloud c = read_point_cloud_ply(dir / "conf.ply", &report);
  ASSERT_EQ(c.confidence.size(), 4u);
  EXPECT_EQ(report.num_invalid_confidence, 3u);
  EXPECT_EQ(c.confidence[0], 0.0f);
  EXPECT_EQ(c.confidence[1], 0.0f);
  EXPECT_EQ(c.confidence[2], 0.0f);
  EXPECT_EQ(c.confidence[3], 2.0f);
}

TEST(PlyIo, ReadsPolygonsAndForeignPropertyNames) {
  hos::testing::TempDir dir;
  std::ofstream(dir / "quad.ply") << "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
                                     "property double z\nproperty uchar r\nproperty uchar g\nproperty uchar b\n"
                                     "element face 1\nproperty list uchar uint vertex_index\nend_header\n"
                                     "0 0 0 1 2 3\n1 0 0 1 2 3\n1 1 0 1 2 3\n0 1 0 1 2 3\n4 0 1 2 3\n";
  const TriangleMesh mesh = read_mesh_ply(dir / "quad.ply");
  EXPECT_EQ(mesh.num_faces(), 2u);
  EXPECT_EQ(mesh.colors[0], (Rgb8{1, 2, 3}));
}

}  // namespace
}  // namespace hos
