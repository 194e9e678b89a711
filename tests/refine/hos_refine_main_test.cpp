// The hos-refine executable: a pass-through run and bad inputs with their exit codes.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/exit_codes.h"
#include "core/ply_io.h"
#include "tests/refine/rock_fixture.h"
#include "tests/support/test_support.h"

namespace hos::refine {
namespace {

using hos::testing::read_text;
using hos::testing::run_command;
using hos::testing::shell_quote;

int run_refine(const std::string& args, const hos::testing::TempDir& dir) {
  return run_command(shell_quote((hos::testing::bin_dir() / "hos-refine").string()) + " --progress none " + args,
                     dir / "log.txt");
}

TEST(HosRefine, DisabledPassesTheMeshThroughAndBadInputsNameTheFile) {
  hos::testing::TempDir dir;
  const TriangleMesh rock = testing::rock_truth();
  write_mesh_ply(dir / "mesh.ply", rock);
  const std::string out = " --output " + shell_quote((dir / "refined.ply").string());
  // Disabled: the mesh as it was, and no workspace is read.
  ASSERT_EQ(run_refine("--mesh " + shell_quote((dir / "mesh.ply").string()) + " --workspace " +
                           shell_quote((dir / "no_workspace").string()) + out + " --set refine.enabled=false",
                       dir),
            kExitSuccess)
      << read_text(dir / "log.txt");
  EXPECT_EQ(read_mesh_ply(dir / "refined.ply").vertices, rock.vertices);
  std::filesystem::remove(dir / "refined.ply");
  // Enabled: a missing workspace is bad input naming it, and nothing is written.
  EXPECT_EQ(run_refine("--mesh " + shell_quote((dir / "mesh.ply").string()) + " --workspace " +
                           shell_quote((dir / "no_workspace").string()) + out + " --set refine.enabled=true",
                       dir),
            kExitBadInput);
  EXPECT_NE(read_text(dir / "log.txt").find("no_workspace"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir / "refined.ply"));
  // A missing mesh, and an option out of range.
  EXPECT_EQ(run_refine("--mesh " + shell_quote((dir / "missing.ply").string()) + " --workspace x" + out, dir),
            kExitBadInput);
  EXPECT_NE(read_text(dir / "log.txt").find("missing.ply"), std::string::npos);
  EXPECT_EQ(run_refine("--mesh m --workspace x" + out + " --set refine.levels=0", dir), kExitUsage);
  EXPECT_EQ(run_refine("--mesh m --workspace x", dir), kExitUsage);
}

}  // namespace
}  // namespace hos::refine
