// The hos-recon executable: a good run, and bad inputs with their exit codes.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>

#include "core/exit_codes.h"
#include "core/ply_io.h"
#include "recon/tiled_reconstruction.h"
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

  // With tiling off, a grid beyond the memory budget is refused up front,
  // naming what fits.
  write_point_cloud_ply(dir / "sphere.ply", synth::sample_sphere(2000, 1.0, 0.0, 2));
  EXPECT_EQ(run_recon("--input " + (dir / "sphere.ply").string() + " --output " + (dir / "big.ply").string() +
                          " --resolution 1024 --max-memory 200 --set recon.tiles=1",
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

std::string file_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(HosRecon, TilesSolvedAsSeparateProcessesJoinToTheSameBytesAsOneProcess) {
  hos::testing::TempDir dir;
  write_point_cloud_ply(dir / "sphere.ply", synth::sample_sphere(20000, 1.0, 0.002, 8));
  const std::string input = "--input " + (dir / "sphere.ply").string() + " --resolution 48 --set recon.tiles=4 ";
  ASSERT_EQ(run_recon(input + "--output " + (dir / "one.ply").string(), dir), kExitSuccess) << log_of(dir);
  EXPECT_NE(log_of(dir).find("grid in 4 tiles (recon.tiles)"), std::string::npos) << log_of(dir);
  EXPECT_FALSE(std::filesystem::exists(dir / "one.ply.tiles")) << "the default tile folder is removed";
  const std::string tiles = (dir / "tiles").string();
  for (int k = 3; k >= 0; --k) {  // in any order
    std::string args = input;
    args += "--tile " + std::to_string(k) + " --tile-dir " + tiles;
    ASSERT_EQ(run_recon(args, dir), kExitSuccess) << log_of(dir);
  }
  ASSERT_EQ(run_recon(input + "--join-tiles " + tiles + " --output " + (dir / "split.ply").string(), dir), kExitSuccess)
      << log_of(dir);
  const std::string one = file_bytes(dir / "one.ply");
  EXPECT_GT(one.size(), 10000u);
  EXPECT_TRUE(one == file_bytes(dir / "split.ply")) << "the split run's mesh differs from one process's";
  EXPECT_TRUE(testing::analyze_topology(read_mesh_ply(dir / "split.ply")).watertight());

  // A tile that is not in the plan is a usage error; a damaged tile file bad input naming it.
  EXPECT_EQ(run_recon(input + "--tile 4 --tile-dir " + tiles, dir), kExitUsage);
  const std::filesystem::path tile2 = dir / "tiles" / "tile-0002.htf";
  std::filesystem::resize_file(tile2, std::filesystem::file_size(tile2) / 2);
  EXPECT_EQ(run_recon(input + "--join-tiles " + tiles + " --output " + (dir / "bad.ply").string(), dir), kExitBadInput);
  EXPECT_NE(log_of(dir).find(tile2.string() + ": truncated"), std::string::npos) << log_of(dir);
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.ply"));
}

TEST(HosRecon, AGridOverTheMemoryBudgetIsReconstructedInTilesAndTheLogSaysSo) {
  hos::testing::TempDir dir;
  // Dense enough that the whole run is watertight at 128.
  const PointCloud points = synth::sample_sphere(60000, 1.0, 0.0, 4);
  write_point_cloud_ply(dir / "sphere.ply", points);
  ReconOptions options;
  options.resolution = 128;
  options.tile_overlap_voxels = 8;
  const std::size_t whole = prepare_tiled_run(points, options, null_reporter()).plan.whole_estimated_peak_bytes;
  const int budget_mb = static_cast<int>(whole / (1024 * 1024) / 2);
  ASSERT_EQ(
      run_recon("--input " + (dir / "sphere.ply").string() + " --output " + (dir / "mesh.ply").string() +
                    " --resolution 128 --set recon.tile_overlap_voxels=8 --max-memory " + std::to_string(budget_mb),
                dir),
      kExitSuccess)
      << log_of(dir);
  EXPECT_NE(log_of(dir).find("exceeds the budget of " + std::to_string(budget_mb) + " MB"), std::string::npos)
      << log_of(dir);
  const TriangleMesh mesh = read_mesh_ply(dir / "mesh.ply");
  EXPECT_TRUE(testing::analyze_topology(mesh).watertight());
  for (const auto& v : mesh.vertices) EXPECT_NEAR(v.norm(), 1.0, 0.01);
}

}  // namespace
}  // namespace hos::recon
