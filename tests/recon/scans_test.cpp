// recon/scans.*: Stanford .conf files and orientation by scan direction.
#include "recon/scans.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/error.h"
#include "core/ply_io.h"
#include "tests/support/test_support.h"

namespace hos::recon {
namespace {

TEST(Scans, EveryPointOfAScanGetsItsDirectionTowardsTheScanner) {
  hos::testing::TempDir dir;
  // Two scans of a unit sphere's caps, each in its own frame where the
  // scanner looks down -z: the cap facing the scanner has z > 0.
  PointCloud cap;
  for (int i = 0; i < 200; ++i) {
    const double a = 0.1 * i, r = 0.5 * (i % 10) / 10.0;
    cap.positions.emplace_back(r * std::cos(a), r * std::sin(a), std::sqrt(1.0 - r * r));
  }
  write_point_cloud_ply(dir / "front.ply", cap, PlyFormat::kAscii);
  write_point_cloud_ply(dir / "back.ply", cap, PlyFormat::kAscii);
  {
    std::ofstream conf(dir / "scans.conf");
    conf << "camera 0 0 1 0 0 0 1\n";
    conf << "bmesh front.ply 0 0 0 0 0 0 1\n";
    // Rotated 180 degrees about y: this scan sees the back (world z < 0).
    conf << "bmesh back.ply 0 0 0 0 1 0 0\n";
  }
  const PointCloud all = load_stanford_scans(dir / "scans.conf", null_reporter());
  ASSERT_EQ(all.size(), 400u);
  for (std::size_t i = 0; i < all.size(); ++i) {
    EXPECT_GT(all.normals[i].dot(all.positions[i]), 0.7f) << i;  // outward on the sphere
  }
}

TEST(Scans, MalformedConfNamesTheFileAndLine) {
  hos::testing::TempDir dir;
  std::ofstream(dir / "bad.conf") << "bmesh a.ply 1 2\n";
  try {
    read_stanford_conf(dir / "bad.conf");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.conf"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("line 1"), std::string::npos);
  }
  EXPECT_THROW(read_stanford_conf(dir / "missing.conf"), InputError);
}

TEST(Scans, OrientByScannerPosition) {
  PointCloud p;
  p.positions = {Eigen::Vector3f(1, 0, 0), Eigen::Vector3f(0, 2, 0)};
  orient_by_scanner_position(p, Eigen::Vector3f(0, 0, 0));
  EXPECT_TRUE(p.normals[0].isApprox(Eigen::Vector3f(-1, 0, 0)));
  EXPECT_TRUE(p.normals[1].isApprox(Eigen::Vector3f(0, -1, 0)));
  orient_by_view_direction(p, Eigen::Vector3f(0, 0, 5));
  EXPECT_TRUE(p.normals[1].isApprox(Eigen::Vector3f(0, 0, 1)));
}

}  // namespace
}  // namespace hos::recon
