// A stage executable's short flags go through the option table: out-of-range,
// negative and NaN values are refused with exit 2 like the same --set, and
// values reach the stage exactly as written (no decimal rounding).
#include <gtest/gtest.h>

#include <fstream>

#include "core/exit_codes.h"
#include "core/ply_io.h"
#include "synth/shapes.h"
#include "tests/support/test_support.h"

namespace hos::apps {
namespace {

namespace fs = std::filesystem;

using hos::testing::run_command;
using hos::testing::shell_quote;

struct ReconRun {
  int exit_code;
  std::string log;
};

ReconRun run_recon(const hos::testing::TempDir& dir, const std::string& flags) {
  ReconRun run;
  run.exit_code = run_command(shell_quote((hos::testing::bin_dir() / "hos-recon").string()) +
                                  " --progress none --input " + shell_quote((dir / "points.ply").string()) +
                                  " --output " + shell_quote((dir / "mesh.ply").string()) + " " + flags,
                              dir / "log.txt");
  std::ifstream in(dir / "log.txt");
  run.log = std::string(std::istreambuf_iterator<char>(in), {});
  return run;
}

class ReconShortFlags : public ::testing::Test {
 protected:
  void SetUp() override { write_point_cloud_ply(dir_ / "points.ply", synth::sample_sphere(2000, 1.0, 0.0, 1)); }
  hos::testing::TempDir dir_;
};

TEST_F(ReconShortFlags, RefuseWhatTheTableRefuses) {
  for (const std::string flags : {"--resolution -3", "--resolution 4", "--voxel-size -1", "--lambda nan", "--lambda -1",
                                  "--energy 7", "--max-memory -5"}) {
    const ReconRun run = run_recon(dir_, flags);
    EXPECT_EQ(run.exit_code, kExitUsage) << flags << "\n" << run.log;
    EXPECT_NE(run.log.find("recon."), std::string::npos) << "names the option: " << run.log;
    EXPECT_FALSE(fs::exists(dir_ / "mesh.ply")) << flags;
  }
}

TEST_F(ReconShortFlags, PassSmallValuesExactly) {
  // 1e-7 read as a decimal string "0.000000" would mean "use the resolution"
  // and succeed; as itself it asks for a grid far beyond any memory budget.
  const ReconRun run = run_recon(dir_, "--voxel-size 1e-7");
  EXPECT_EQ(run.exit_code, kExitUsage) << run.log;
  EXPECT_NE(run.log.find("recon.voxel_size"), std::string::npos) << run.log;
}

TEST_F(ReconShortFlags, WinOverSet) {
  // 2048 would be refused by the 200 MB budget; the flag, applied last, asks for 16.
  const ReconRun run = run_recon(dir_, "--max-memory 200 --set recon.resolution=2048 --resolution 16");
  EXPECT_EQ(run.exit_code, kExitSuccess) << run.log;
}

}  // namespace
}  // namespace hos::apps
