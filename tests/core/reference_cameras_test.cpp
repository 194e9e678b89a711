#include "core/reference_cameras.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <fstream>

#include "core/error.h"
#include "tests/support/test_support.h"

namespace hos {
namespace {

Eigen::Matrix3d some_rotation() {
  return Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
}

TEST(ReferenceCameras, MiddleburyCentreIsMinusRTransposeT) {
  hos::testing::TempDir dir;
  const Eigen::Matrix3d r = some_rotation();
  const Eigen::Vector3d centre(0.5, -1.0, 2.0);
  const Eigen::Vector3d t = -r * centre;
  {
    std::ofstream out(dir / "set_par.txt");
    out.precision(17);
    out << "1\nview01.png 1000 0 320 0 1000 240 0 0 1";
    for (int i = 0; i < 9; ++i) out << ' ' << r(i / 3, i % 3);
    out << ' ' << t.x() << ' ' << t.y() << ' ' << t.z() << "\n";
  }
  const auto poses = read_middlebury_cameras(dir / "set_par.txt");
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_LT((poses.at("view01.png").centre - centre).norm(), 1e-9);
  EXPECT_LT((poses.at("view01.png").cam_from_world - r).norm(), 1e-9);

  std::ofstream(dir / "short_par.txt") << "2\nview01.png 1 2 3\n";
  try {
    read_middlebury_cameras(dir / "short_par.txt");
    FAIL() << "a truncated file was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("short_par.txt"), std::string::npos) << e.what();
  }
}

TEST(ReferenceCameras, StrechaStoresCameraToWorldRotationAndCentre) {
  hos::testing::TempDir dir;
  const Eigen::Matrix3d world_from_cam = some_rotation();
  const Eigen::Vector3d centre(3.0, 4.0, -5.0);
  {
    std::ofstream out(dir / "0000.jpg.camera");
    out.precision(17);
    out << "2000 0 1500\n0 2000 1000\n0 0 1\n0 0 0\n";
    for (int i = 0; i < 9; ++i) out << world_from_cam(i / 3, i % 3) << (i % 3 == 2 ? '\n' : ' ');
    out << centre.x() << ' ' << centre.y() << ' ' << centre.z() << "\n3072 2048\n";
  }
  std::ofstream(dir / "notes.txt") << "not a camera";
  const auto poses = read_strecha_cameras(dir.path());
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_LT((poses.at("0000.jpg").centre - centre).norm(), 1e-9);
  EXPECT_LT((poses.at("0000.jpg").cam_from_world - world_from_cam.transpose()).norm(), 1e-9);
  EXPECT_THROW(read_strecha_cameras(dir / "missing"), InputError);
}

}  // namespace
}  // namespace hos
