// The hos-recon executable: a good run, and bad inputs with their exit codes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>

#include "core/exit_codes.h"
#include "core/ply_io.h"
#include "synth/shapes.h"
#include "tests/recon/shape_samples.h"
#include "tests/support/test_support.h"

namespace hos::recon {
namespace {

using hos::testing::run_command;
using hos::testing::shell_quote;

int run_recon(const std::string& args, const hos::testing::TempDir& dir) {
  return run_command(shell_quote((hos::testing::bin_dir() / "hos-recon").string()) + " --progress none " + args,
                     dir / "log.txt");
}

std::string log_of(const hos::testing::TempDir& dir) {
  std::ifstream in(dir / "log.txt");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(HosRecon, ReconstructsASphereFile) {
  hos::testing::TempDir dir;
  write_point_cloud_ply(dir / "points.ply", synth::sample_sphere(20000, 1.0, 0.002, 1));
  ASSERT_EQ(run_recon("--input " + (dir / "points.ply").string() + " --output " + (dir / "mesh.ply").string() +
                          " --resolution 32",
                      dir),
            kExitSuccess)
      << log_of(dir);
  const TriangleMesh mesh = read_mesh_ply(dir / "mesh.ply");
  EXPECT_TRUE(testing::analyze_topology(mesh).watertight());
  for (const auto& v : mesh.vertices) EXPECT_NEAR(v.norm(), 1.0, 0.08);
}

TEST(HosRecon, BadInputsGetAClearMessageAndExitCode) {
  hos::testing::TempDir dir;
  const std::string out = " --output " + (dir / "mesh.ply").string();
  EXPECT_EQ(run_recon("--input " + (dir / "missing.ply").string() + out, dir), kExitBadInput);
  EXPECT_NE(log_of(dir).find("missing.ply"), std::string::npos);

  PointCloud unoriented = synth::sample_sphere(1000, 1.0, 0.0, 2);
  unoriented.normals.clear();
  write_point_cloud_ply(dir / "unoriented.ply", unoriented);
  EXPECT_EQ(run_recon("--input " + (dir / "unoriented.ply").string() + out, dir), kExitBadInput);
  EXPECT_NE(log_of(dir).find("no normals"), std::string::npos);
  // The same points oriented from a scanner position inside reconstruct
  // (inward normals, so the surface is still found).
  EXPECT_EQ(
      run_recon("--input " + (dir / "unoriented.ply").string() + out + " --resolution 16 --scanner-pos 0,0,0", dir),
      kExitSuccess)
      << log_of(dir);

  PointCloud one;
  one.positions = {Eigen::Vector3f(0, 0, 0)};
  one.normals = {Eigen::Vector3f(0, 0, 1)};
  write_point_cloud_ply(dir / "one.ply", one);
  EXPECT_EQ(run_recon("--input " + (dir / "one.ply").string() + out, dir), kExitBadInput);

  std::ofstream(dir / "garbage.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n";
  EXPECT_EQ(run_recon("--input " + (dir / "garbage.ply").string() + out, dir), kExitBadInput);
  EXPECT_NE(log_of(dir).find("garbage.ply"), std::string::npos);

  EXPECT_EQ(run_recon("--input a.ply", dir), kExitUsage);
  EXPECT_EQ(run_recon("--input " + (dir / "one.ply").string() + out + " --set recon.lamda=1", dir), kExitUsage);
  EXPECT_NE(log_of(dir).find("lambda"), std::string::npos) << "closest valid key";

  // A grid beyond the memory budget is refused up front, naming what fits.
  write_point_cloud_ply(dir / "sphere.ply", synth::sample_sphere(2000, 1.0, 0.0, 2));
  EXPECT_EQ(run_recon("--input " + (dir / "sphere.ply").string() + " --output " + (dir / "big.ply").string() +
                          " --resolution 1024 --max-memory 200",
                      dir),
            kExitUsage);
  EXPECT_NE(log_of(dir).find("largest resolution that fits"), std::string::npos) << log_of(dir);
  EXPECT_FALSE(std::filesystem::exists(dir / "big.ply"));
  EXPECT_FALSE(std::filesystem::exists(dir / "mesh.ply.tmp"));
}

TEST(HosRecon, OutputThatIsAFolderIsRefusedBeforeTheSolve) {
  hos::testing::TempDir dir;
  write_point_cloud_ply(dir / "sphere.ply", synth::sample_sphere(2000, 1.0, 0.0, 3));
  std::filesystem::create_directories(dir / "mesh.ply");
  EXPECT_EQ(run_recon("--input " + (dir / "sphere.ply").string() + " --output " + (dir / "mesh.ply").string() +
                          " --resolution 16",
                      dir),
            kExitOutputFailed);
  EXPECT_NE(log_of(dir).find("is a folder"), std::string::npos) << log_of(dir);
  EXPECT_EQ(log_of(dir).find("CG iterations"), std::string::npos) << "detected only after the solve";
}

TEST(HosRecon, UnusableConfidencesAreCountedInAWarning) {
  hos::testing::TempDir dir;
  PointCloud points = synth::sample_sphere(4000, 1.0, 0.0, 4);
  points.confidence.assign(points.size(), 1.0f);
  points.confidence[0] = std::numeric_limits<float>::quiet_NaN();
  points.confidence[1] = -2.0f;
  write_point_cloud_ply(dir / "points.ply", points);
  EXPECT_EQ(run_recon("--input " + (dir / "points.ply").string() + " --output " + (dir / "mesh.ply").string() +
                          " --resolution 16",
                      dir),
            kExitSuccess)
      << log_of(dir);
  EXPECT_NE(log_of(dir).find("'confidence' is NaN, infinite or negative at 2 points"), std::string::npos)
      << log_of(dir);
}

}  // namespace
}  // namespace hos::recon
