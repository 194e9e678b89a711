// pipeline/stages.*: the stage table. Every stage carries every fact the
// driver, the Slurm executor and the report read from it, so adding a stage
// is adding one entry; the disk estimates grow with what each stage reads.
#include "pipeline/stages.h"

#include <gtest/gtest.h>

#include <fstream>
#include <map>

#include "core/error.h"
#include "pipeline/slurm/slurm_options.h"
#include "tests/support/test_support.h"

namespace hos::pipeline {
namespace {
namespace fs = std::filesystem;
using hos::testing::TempDir;

constexpr std::uintmax_t kMB = 1024 * 1024;

void write_bytes(const fs::path& file, std::uintmax_t bytes) {
  fs::create_directories(file.parent_path());
  std::ofstream out(file, std::ios::binary);
  out << std::string(bytes, 'x');
}

TEST(StageTable, ListsTheFiveStagesInOrder) {
  std::vector<std::string> names;
  for (const StageSpec& spec : pipeline_stages()) names.push_back(spec.name);
  EXPECT_EQ(names, (std::vector<std::string>{"sfm", "mvs", "recon", "refine", "texture"}));
  EXPECT_EQ(stage_names_text(", "), "sfm, mvs, recon, refine, texture");
}

TEST(StageTable, EveryStageHasEveryFact) {
  for (const StageSpec& spec : pipeline_stages()) {
    SCOPED_TRACE(spec.name);
    EXPECT_EQ(spec.executable, "hos-" + spec.name);
    EXPECT_TRUE(spec.arguments);
    EXPECT_TRUE(spec.inputs);
    EXPECT_TRUE(spec.output_exists);
    ASSERT_TRUE(spec.make_config);
    EXPECT_NE(spec.make_config(), nullptr);
    EXPECT_TRUE(spec.disk_bytes);
    EXPECT_TRUE(spec.job_memory_mb);
    EXPECT_TRUE(spec.job_cpu_seconds);
    EXPECT_TRUE(spec.read_figures);
    EXPECT_TRUE(spec.figures_text);
    EXPECT_TRUE(spec.plots);
    if (!spec.split) continue;
    EXPECT_FALSE(spec.split->part_name.empty());
    EXPECT_FALSE(spec.split->join_name.empty());
    EXPECT_TRUE(spec.split->part_arguments);
    EXPECT_TRUE(spec.split->join_arguments);
    // Its parts are fixed by its options, or chunks of the views set by an executor option.
    EXPECT_NE(bool(spec.split->fixed_parts), !spec.split->tasks_option.empty());
    if (!spec.split->tasks_option.empty()) {
      EXPECT_FALSE(spec.split->parts_text.empty());
    }
  }
}

TEST(StageTable, SplitStagesTakeTheirTasksOption) {
  int splitting = 0;
  for (const StageSpec& spec : pipeline_stages()) {
    if (!spec.split || spec.split->tasks_option.empty()) continue;
    ++splitting;
    EXPECT_EQ(parse_slurm_options({spec.split->tasks_option + "=7"}).tasks_of(spec.name), 7) << spec.name;
    EXPECT_EQ(parse_slurm_options({}).tasks_of(spec.name), kDefaultArrayTasks) << spec.name;
  }
  EXPECT_EQ(splitting, 2);  // mvs and texture
  EXPECT_THROW(parse_slurm_options({}).tasks_of("sfm"), ConfigError);
}

TEST(StageTable, JobNamesMapToTheirStageAndJob) {
  const StageSpec* spec = nullptr;
  StageJob kind = StageJob::kWhole;
  ASSERT_TRUE(find_stage_job("mvs-depth", spec, kind));
  EXPECT_EQ(spec->name, "mvs");
  EXPECT_EQ(kind, StageJob::kPart);
  ASSERT_TRUE(find_stage_job("texture-atlas", spec, kind));
  EXPECT_EQ(spec->name, "texture");
  EXPECT_EQ(kind, StageJob::kJoin);
  ASSERT_TRUE(find_stage_job("refine", spec, kind));
  EXPECT_EQ(spec->name, "refine");
  EXPECT_EQ(kind, StageJob::kWhole);
  EXPECT_FALSE(find_stage_job("refine-views", spec, kind));
  EXPECT_FALSE(find_stage_job("eval", spec, kind));
}

// Each estimate covers the scratch files and grows by at least the size of
// what the stage reads (its result is about that size or larger); refine's
// included.
TEST(StageTable, DiskEstimatesGrowWithEachStagesInput) {
  TempDir dir;
  const fs::path photos = dir / "photos";
  fs::create_directories(photos);
  const StagePaths paths(dir / "ws");
  std::map<std::string, std::uintmax_t> empty;
  for (const StageSpec& spec : pipeline_stages()) {
    empty[spec.name] = spec.disk_bytes(photos, paths);
    EXPECT_GE(empty[spec.name], 16 * kMB) << spec.name;  // logs, reports, small files
  }
  write_bytes(photos / "a.jpg", 3 * kMB);
  write_bytes(paths.undistorted / "images" / "a.jpg", 2 * kMB);
  write_bytes(paths.points, 4 * kMB);
  write_bytes(paths.mesh, 5 * kMB);
  write_bytes(paths.refined_mesh, 6 * kMB);
  const std::map<std::string, std::uintmax_t> input{
      {"sfm", 3 * kMB}, {"mvs", 2 * kMB}, {"recon", 4 * kMB}, {"refine", 5 * kMB}, {"texture", 6 * kMB}};
  for (const StageSpec& spec : pipeline_stages()) {
    const std::uintmax_t grown = spec.disk_bytes(photos, paths);
    EXPECT_GE(grown, empty[spec.name] + input.at(spec.name)) << spec.name;
    EXPECT_LE(grown, empty[spec.name] + 4 * (3 + 2 + 4 + 5 + 6) * kMB) << spec.name;  // not wildly more
  }
}

TEST(StageTable, AMissingOutputHasNoPlots) {
  TempDir dir;
  for (const StageSpec& spec : pipeline_stages()) {
    SCOPED_TRACE(spec.name);
    EXPECT_TRUE(spec.plots(StagePaths(dir.path())).empty());
  }
}

}  // namespace
}  // namespace hos::pipeline
