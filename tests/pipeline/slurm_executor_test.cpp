// pipeline/slurm_executor.*: the submitted scripts, dependencies, array
// ranges, resume and cancel, with shell scripts on PATH standing in for
// sbatch, squeue, sacct and scancel (the one-node Slurm test is
// slurm_cluster_test.cpp).
#include "pipeline/slurm/slurm_executor.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdlib>
#include <fstream>
#include <functional>
#include <iterator>
#include <sstream>

#include "core/error.h"
#include "core/subprocess.h"
#include "pipeline/driver.h"
#include "tests/support/message_log.h"
#include "tests/support/test_support.h"

namespace hos::pipeline {
namespace {
namespace fs = std::filesystem;
using hos::testing::read_text;
using ::testing::HasSubstr;
using ::testing::Not;

// sbatch records its arguments (one call a line) and the script, and answers
// job ids from 100 on; squeue runs the script on_squeue_<n> on its n-th call
// if there is one (jobs finishing while the driver waits), then lists the
// ids in active.txt; sacct prints sacct.txt; scancel records its arguments.
constexpr const char* kFakeSbatch = R"(#!/bin/sh
n=$(cat "$HOS_FAKE_SLURM/next_id" 2>/dev/null || echo 100)
echo "$*" >> "$HOS_FAKE_SLURM/sbatch.log"
for last; do :; done
cp "$last" "$HOS_FAKE_SLURM/script.$n.sh"
echo $((n + 1)) > "$HOS_FAKE_SLURM/next_id"
echo "$n"
)";
constexpr const char* kFakeSqueue = R"(#!/bin/sh
n=$(($(cat "$HOS_FAKE_SLURM/squeue_calls" 2>/dev/null || echo 0) + 1))
echo "$n" > "$HOS_FAKE_SLURM/squeue_calls"
if [ -f "$HOS_FAKE_SLURM/on_squeue_$n" ]; then sh "$HOS_FAKE_SLURM/on_squeue_$n"; fi
cat "$HOS_FAKE_SLURM/active.txt" 2>/dev/null
exit 0
)";
constexpr const char* kFakeSacct = R"(#!/bin/sh
cat "$HOS_FAKE_SLURM/sacct.txt" 2>/dev/null
exit 0
)";
// sinfo answers a partition, as a reachable controller does.
constexpr const char* kFakeSinfo = R"(#!/bin/sh
echo debug
)";
constexpr const char* kFakeScancel = R"(#!/bin/sh
echo "$*" >> "$HOS_FAKE_SLURM/scancel.log"
)";
// A stage executable that records its arguments.
constexpr const char* kRecordingStage = R"(#!/bin/sh
echo "$(basename "$0") $*" >> "$HOS_FAKE_SLURM/stage_calls"
)";

void write_executable(const fs::path& file, const std::string& text) {
  std::ofstream(file) << text;
  fs::permissions(file, fs::perms::owner_all);
}

std::vector<std::string> lines_of(const fs::path& file) {
  std::vector<std::string> lines;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

class AlwaysCancellingReporter : public testing::MessageLog {
 public:
  bool cancel_requested() const override { return true; }
};

class SlurmExecutorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::create_directories(fake_);
    fs::create_directories(bin_);
    fs::create_directories(photos_);
    for (const char* name : {"p0", "p1", "p2", "p3", "p4", "p5", "p6", "p7", "p8", "p9"}) {
      std::ofstream(photos_ / (std::string(name) + ".jpg")) << "x";
    }
    write_executable(fake_ / "sbatch", kFakeSbatch);
    write_executable(fake_ / "squeue", kFakeSqueue);
    write_executable(fake_ / "sacct", kFakeSacct);
    write_executable(fake_ / "scancel", kFakeScancel);
    write_executable(fake_ / "sinfo", kFakeSinfo);
    for (const char* exe : {"hos-sfm", "hos-mvs", "hos-recon", "hos-refine", "hos-texture"}) {
      write_executable(bin_ / exe, kRecordingStage);
    }
    old_path_ = std::getenv("PATH") ? std::getenv("PATH") : "";
    setenv("PATH", (fake_.string() + ":" + old_path_).c_str(), 1);
    setenv("HOS_FAKE_SLURM", fake_.c_str(), 1);
    options_.photos = photos_;
    options_.output = dir_.path() / "out.glb";
    options_.bin_dir = bin_;
    options_.executor = "slurm";
    options_.executor_options = {"mvs_tasks=3", "wait=false", "partition=gpu", "account=lab"};
  }
  void TearDown() override { setenv("PATH", old_path_.c_str(), 1); }

  std::vector<std::string> sbatch_calls() const { return lines_of(fake_ / "sbatch.log"); }
  fs::path ws() const { return dir_.path() / "out_workspace"; }
  void set_status(const std::string& name, int code) {
    fs::create_directories(ws() / "slurm" / "status");
    std::ofstream(ws() / "slurm" / "status" / (name + ".exit")) << code << "\n";
  }
  // Shell commands that write what set_status and write_sfm_outputs write,
  // run by the n-th squeue call.
  void on_squeue_call(int n, const std::vector<std::string>& statuses, bool sfm_outputs) {
    std::ofstream out(fake_ / ("on_squeue_" + std::to_string(n)));
    const fs::path status = ws() / "slurm" / "status";
    out << "mkdir -p '" << status.string() << "'\n";
    for (const auto& s : statuses) {
      const auto eq = s.find('=');
      out << "echo " << s.substr(eq + 1) << " > '" << (status / (s.substr(0, eq) + ".exit")).string() << "'\n";
    }
    if (sfm_outputs) {
      out << "mkdir -p '" << (ws() / "sfm" / "undistorted" / "sparse").string() << "'\n";
      out << "echo '# none' > '" << (ws() / "sfm" / "undistorted" / "sparse" / "cameras.txt").string() << "'\n";
      out << "echo '{}' > '" << (ws() / "sfm" / "report.json").string() << "'\n";
    }
  }
  void set_active(const std::vector<std::string>& ids) {
    std::ofstream out(fake_ / "active.txt");
    for (const auto& id : ids) out << id << "\n";
  }
  // What hos-sfm leaves behind, so the sfm stage counts as done.
  void write_sfm_outputs() {
    fs::create_directories(ws() / "sfm" / "undistorted" / "sparse");
    std::ofstream(ws() / "sfm" / "undistorted" / "sparse" / "cameras.txt") << "# none\n";
    std::ofstream(ws() / "sfm" / "report.json") << "{}\n";
  }
  nlohmann::json run_json() const { return nlohmann::json::parse(read_text(ws() / "run.json")); }

  // Every job of a first submission: sfm, mvs-depth's 3 tasks, mvs-fuse,
  // recon, refine, texture-views' 4 tasks, texture-atlas.
  const std::vector<std::string> kAllJobs{"100", "101_0", "101_1", "101_2", "102",   "103",
                                          "104", "105_0", "105_1", "105_2", "105_3", "106"};
  testing::TempDir dir_{"hos-slurm"};
  fs::path fake_ = dir_.path() / "fake_slurm";
  fs::path bin_ = dir_.path() / "bin";
  fs::path photos_ = dir_.path() / "photos";
  std::string old_path_;
  DriverOptions options_;
  testing::MessageLog log_;
};

TEST_F(SlurmExecutorTest, SubmitsEveryStageAfterTheOneBeforeAndMvsAndTextureAsArraysThenAJoin) {
  run_pipeline(options_, log_);
  const auto calls = sbatch_calls();
  ASSERT_EQ(calls.size(), 7u) << log_.all();
  const fs::path scripts = ws() / "slurm";
  EXPECT_EQ(calls[0], std::string("--parsable ") + (scripts / "sfm.sh").string());
  // 10 photos in 3 tasks: 4 views a task (the last one has 2).
  EXPECT_EQ(calls[1],
            std::string("--parsable --array=0,1,2 --dependency=afterok:100 ") + (scripts / "mvs-depth.sh").string());
  EXPECT_EQ(calls[2], std::string("--parsable --dependency=afterok:101 ") + (scripts / "mvs-fuse.sh").string());
  EXPECT_EQ(calls[3], std::string("--parsable --dependency=afterok:102 ") + (scripts / "recon.sh").string());
  EXPECT_EQ(calls[4], std::string("--parsable --dependency=afterok:103 ") + (scripts / "refine.sh").string());
  // texture_tasks is 4 by default: 3 views a task.
  EXPECT_EQ(calls[5], std::string("--parsable --array=0,1,2,3 --dependency=afterok:104 ") +
                          (scripts / "texture-views.sh").string());
  EXPECT_EQ(calls[6], std::string("--parsable --dependency=afterok:105 ") + (scripts / "texture-atlas.sh").string());

  const std::string depth = read_text(fake_ / "script.101.sh");
  EXPECT_THAT(depth, HasSubstr("#SBATCH --job-name=hos-mvs-depth\n"));
  EXPECT_THAT(depth, HasSubstr("#SBATCH --partition=gpu\n"));
  EXPECT_THAT(depth, HasSubstr("#SBATCH --account=lab\n"));
  EXPECT_THAT(depth, HasSubstr("#SBATCH --mem="));
  EXPECT_THAT(depth, HasSubstr("first=$((task * 4))"));
  EXPECT_THAT(read_text(fake_ / "script.105.sh"), HasSubstr("first=$((task * 3))"));
  EXPECT_THAT(read_text(fake_ / "script.105.sh"), HasSubstr("#SBATCH --job-name=hos-texture-views\n"));
  EXPECT_THAT(read_text(fake_ / "script.100.sh"), Not(HasSubstr("--mem=")));  // sfm has no estimate
  // Time from the stages' estimates: 10 photos of sfm are well under the
  // 10 minutes every request gets at least; texture cannot estimate
  // without a photo it can read (these are not photos).
  EXPECT_THAT(read_text(fake_ / "script.100.sh"), HasSubstr("#SBATCH --time=00:10:00\n"));
  EXPECT_THAT(depth, HasSubstr("#SBATCH --time="));
  EXPECT_THAT(read_text(fake_ / "script.105.sh"), Not(HasSubstr("--time=")));

  const nlohmann::json record = run_json();
  EXPECT_EQ(record["slurm"]["jobs"]["sfm"]["tasks"]["0"], "100");
  EXPECT_EQ(record["slurm"]["jobs"]["mvs-depth"]["tasks"]["2"], "101_2");
  EXPECT_EQ(record["slurm"]["jobs"]["texture-views"]["tasks"]["3"], "105_3");
  EXPECT_EQ(record["slurm"]["jobs"]["texture-atlas"]["tasks"]["0"], "106");
  EXPECT_EQ(record["stages"]["mvs"]["state"], "submitted");
  EXPECT_THAT(read_text(ws() / "report.html"), HasSubstr("sfm</b>: it was submitted to Slurm and had not finished"));
}

TEST_F(SlurmExecutorTest, TimeOptionOverridesEveryEstimate) {
  options_.executor_options.push_back("time=1-12:00:00");
  run_pipeline(options_, log_);
  for (int id = 100; id <= 106; ++id) {
    EXPECT_THAT(read_text(fake_ / ("script." + std::to_string(id) + ".sh")), HasSubstr("#SBATCH --time=1-12:00:00\n"))
        << id;
  }
}

TEST_F(SlurmExecutorTest, ArrayTaskScriptRunsItsViewChunkAndRecordsItsExitCode) {
  run_pipeline(options_, log_);
  ProcessOptions process;
  process.argv = {"/bin/sh", (ws() / "slurm" / "mvs-depth.sh").string()};
  process.environment = {{"SLURM_ARRAY_TASK_ID", "1"}};
  ASSERT_TRUE(run_process(process).ok());
  const std::string calls = read_text(fake_ / "stage_calls");
  EXPECT_THAT(calls, HasSubstr(std::string("hos-mvs --workspace ") + (ws() / "sfm" / "undistorted").string() +
                               std::string(" --views 4-7 --depth-maps ") + (ws() / "mvs" / "depth_maps").string()));
  EXPECT_THAT(calls, HasSubstr(std::string("--log ") + (ws() / "logs" / "mvs-depth.1.log").string()));
  // Exit code, wall seconds, and the user and system time of `times`.
  EXPECT_THAT(read_text(ws() / "slurm" / "status" / "mvs-depth.1.exit"),
              ::testing::MatchesRegex("0 [0-9]+ [0-9]+m[0-9.]+s [0-9]+m[0-9.]+s\n"));
  EXPECT_FALSE(fs::exists(ws() / "slurm" / "status" / "mvs-depth.1.exit.times"));
}

TEST_F(SlurmExecutorTest, TextureTaskScriptsComputeTheirViewChunkAndTheJoinReadsTheFolder) {
  run_pipeline(options_, log_);
  for (const std::string job : {"texture-views", "texture-atlas"}) {
    ProcessOptions process;
    process.argv = {"/bin/sh", (ws() / "slurm" / (job + ".sh")).string()};
    process.environment = {{"SLURM_ARRAY_TASK_ID", "2"}};
    ASSERT_TRUE(run_process(process).ok()) << job;
  }
  const auto calls = lines_of(fake_ / "stage_calls");
  ASSERT_EQ(calls.size(), 2u);
  const std::string workspace_and_mesh = std::string("hos-texture --workspace ") +
                                         (ws() / "sfm" / "undistorted").string() + " --mesh " +
                                         (ws() / "refine" / "mesh.ply").string();
  const std::string view_data = (ws() / "texture" / "view_data").string();
  EXPECT_THAT(calls[0], HasSubstr(workspace_and_mesh + " --views 6-8 --view-data " + view_data + " "));
  EXPECT_THAT(calls[0], HasSubstr(std::string("--log ") + (ws() / "logs" / "texture-views.2.log").string()));
  EXPECT_THAT(calls[0], Not(HasSubstr("--output")));
  EXPECT_THAT(calls[1], HasSubstr(workspace_and_mesh + " --from-view-data " + view_data + " --output " +
                                  (ws() / "texture" / "model.glb").string()));
  EXPECT_THAT(calls[1], HasSubstr(std::string("--log ") + (ws() / "logs" / "texture.log").string()));
  EXPECT_TRUE(fs::exists(ws() / "slurm" / "status" / "texture-views.2.exit"));
  EXPECT_TRUE(fs::exists(ws() / "slurm" / "status" / "texture-atlas.exit"));
}

TEST_F(SlurmExecutorTest, ReRunSubmitsOnlyTheFailedArrayTaskAndWhatFollowsIt) {
  run_pipeline(options_, log_);
  write_sfm_outputs();
  set_status("sfm", 0);
  set_status("mvs-depth.0", 0);
  set_status("mvs-depth.2", 0);
  // Task 1 was killed (no status file); Slurm forgot it, sacct says why.
  std::ofstream(fake_ / "sacct.txt") << "101_1|CANCELLED by 0\n";
  // The fuse was cancelled when task 1 failed; nothing is active.
  run_pipeline(options_, log_);
  const auto calls = sbatch_calls();
  ASSERT_EQ(calls.size(), 13u) << log_.all();
  EXPECT_EQ(calls[7], std::string("--parsable --array=1 ") + (ws() / "slurm" / "mvs-depth.sh").string());
  EXPECT_THAT(calls[8], HasSubstr("--dependency=afterok:107 "));
  EXPECT_THAT(calls[8], HasSubstr("mvs-fuse.sh"));
  // Every texture task again: its input (the mesh) will change.
  EXPECT_THAT(calls[11], HasSubstr("--array=0,1,2,3 "));
  EXPECT_THAT(calls[11], HasSubstr("texture-views.sh"));
  EXPECT_THAT(calls[12], HasSubstr("texture-atlas.sh"));
  EXPECT_THAT(log_.all(), HasSubstr("CANCELLED by 0"));
  const nlohmann::json record = run_json();
  EXPECT_EQ(record["stages"]["sfm"]["state"], "done");
  EXPECT_EQ(record["slurm"]["jobs"]["sfm"]["tasks"]["0"], "100");
  EXPECT_EQ(record["slurm"]["jobs"]["mvs-depth"]["tasks"]["0"], "101_0");
  EXPECT_EQ(record["slurm"]["jobs"]["mvs-depth"]["tasks"]["1"], "107_1");
  EXPECT_EQ(record["slurm"]["jobs"]["mvs-depth"]["tasks"]["2"], "101_2");
}

TEST_F(SlurmExecutorTest, ReRunAfterAFailedTextureTaskSubmitsOnlyThatTaskAndTheJoin) {
  run_pipeline(options_, log_);
  write_sfm_outputs();
  for (const char* file : {"mvs/points.ply", "recon/mesh.ply", "refine/mesh.ply"}) {
    fs::create_directories((ws() / file).parent_path());
    std::ofstream(ws() / file) << "result " << file;
  }
  for (const char* job : {"sfm", "mvs-depth.0", "mvs-depth.1", "mvs-depth.2", "mvs-fuse", "recon", "refine",
                          "texture-views.0", "texture-views.1", "texture-views.3"}) {
    set_status(job, 0);
  }
  set_status("texture-views.2", 3);  // its input was bad; the join never started (afterok)
  run_pipeline(options_, log_);
  const auto calls = sbatch_calls();
  ASSERT_EQ(calls.size(), 9u) << log_.all();
  EXPECT_EQ(calls[7], std::string("--parsable --array=2 ") + (ws() / "slurm" / "texture-views.sh").string());
  EXPECT_EQ(calls[8],
            std::string("--parsable --dependency=afterok:107 ") + (ws() / "slurm" / "texture-atlas.sh").string());
  EXPECT_THAT(log_.all(), HasSubstr("texture-views task 2 (job 105_2) exit code 3; submitting it again"));
  const nlohmann::json record = run_json();
  for (const char* stage : {"sfm", "mvs", "recon", "refine"}) EXPECT_EQ(record["stages"][stage]["state"], "done");
  const auto& tasks = record["slurm"]["jobs"]["texture-views"]["tasks"];
  EXPECT_EQ(tasks["0"], "105_0");
  EXPECT_EQ(tasks["2"], "107_2");
  EXPECT_EQ(tasks["3"], "105_3");
  EXPECT_EQ(record["slurm"]["jobs"]["texture-atlas"]["tasks"]["0"], "108");
}

// recon.tiles: 3 makes recon a 3-task array (one tile each) and a join after
// it, each asking for recon's budget; the stages after wait for the join.
TEST_F(SlurmExecutorTest, TiledReconIsAnArrayOfOneTaskPerTileThenAJoin) {
  options_.assignments = {"recon.tiles=3", "recon.max_memory_mb=2000"};
  run_pipeline(options_, log_);
  const auto calls = sbatch_calls();
  ASSERT_EQ(calls.size(), 8u) << log_.all();
  const fs::path scripts = ws() / "slurm";
  EXPECT_EQ(calls[3],
            std::string("--parsable --array=0,1,2 --dependency=afterok:102 ") + (scripts / "recon-tiles.sh").string());
  EXPECT_EQ(calls[4], std::string("--parsable --dependency=afterok:103 ") + (scripts / "recon-join.sh").string());
  EXPECT_EQ(calls[5], std::string("--parsable --dependency=afterok:104 ") + (scripts / "refine.sh").string());
  for (const int id : {103, 104}) {
    const std::string script = read_text(fake_ / ("script." + std::to_string(id) + ".sh"));
    EXPECT_THAT(script, HasSubstr("#SBATCH --mem=2512M\n")) << id;
    EXPECT_THAT(script, Not(HasSubstr("first="))) << id;  // tiles, not views
  }
  EXPECT_THAT(read_text(fake_ / "script.103.sh"), HasSubstr("#SBATCH --job-name=hos-recon-tiles\n"));

  for (const std::string job : {"recon-tiles", "recon-join"}) {
    ProcessOptions process;
    process.argv = {"/bin/sh", (scripts / (job + ".sh")).string()};
    process.environment = {{"SLURM_ARRAY_TASK_ID", "2"}};
    ASSERT_TRUE(run_process(process).ok()) << job;
  }
  const auto stage_calls = lines_of(fake_ / "stage_calls");
  ASSERT_EQ(stage_calls.size(), 2u);
  const std::string input = std::string("hos-recon --input ") + (ws() / "mvs" / "points.ply").string();
  const std::string tiles = (ws() / "recon" / "tiles").string();
  EXPECT_THAT(stage_calls[0], HasSubstr(input + " --tile 2 --tile-dir " + tiles + " "));
  EXPECT_THAT(stage_calls[0], HasSubstr(std::string("--log ") + (ws() / "logs" / "recon-tiles.2.log").string()));
  EXPECT_THAT(stage_calls[0], Not(HasSubstr("--output")));
  EXPECT_THAT(stage_calls[1], HasSubstr(input + " --join-tiles " + tiles + " --output " +
                                        (ws() / "recon" / "mesh.ply").string() + " --report "));
  EXPECT_THAT(stage_calls[1], HasSubstr(std::string("--log ") + (ws() / "logs" / "recon.log").string()));
  EXPECT_TRUE(fs::exists(ws() / "slurm" / "status" / "recon-tiles.2.exit"));
  EXPECT_TRUE(fs::exists(ws() / "slurm" / "status" / "recon-join.exit"));

  const nlohmann::json record = run_json();
  EXPECT_EQ(record["slurm"]["jobs"]["recon-tiles"]["tasks"]["2"], "103_2");
  EXPECT_EQ(record["slurm"]["jobs"]["recon-join"]["tasks"]["0"], "104");
  EXPECT_FALSE(record["slurm"]["jobs"].contains("recon"));
}

// recon.tiles 1 never tiles, 0 tiles only when the points' grid exceeds the
// budget, which is not known before mvs: one job either way.
TEST_F(SlurmExecutorTest, ReconWithoutATileCountIsOneJob) {
  for (const char* tiles : {"recon.tiles=0", "recon.tiles=1"}) {
    options_.assignments = {tiles};
    run_pipeline(options_, log_);
    const auto calls = sbatch_calls();
    ASSERT_EQ(calls.size() % 7, 0u) << tiles << log_.all();
    EXPECT_THAT(calls[calls.size() - 4], HasSubstr((ws() / "slurm" / "recon.sh").string())) << tiles;
  }
}

TEST_F(SlurmExecutorTest, ReRunAfterAFailedTileSubmitsOnlyThatTileAndTheJoinAndWhatFollows) {
  options_.assignments = {"recon.tiles=3"};
  run_pipeline(options_, log_);
  write_sfm_outputs();
  fs::create_directories(ws() / "mvs");
  std::ofstream(ws() / "mvs" / "points.ply") << "points";
  for (const char* job :
       {"sfm", "mvs-depth.0", "mvs-depth.1", "mvs-depth.2", "mvs-fuse", "recon-tiles.0", "recon-tiles.2"}) {
    set_status(job, 0);
  }
  set_status("recon-tiles.1", 2);  // the join never started (afterok)
  run_pipeline(options_, log_);
  const auto calls = sbatch_calls();
  ASSERT_EQ(calls.size(), 13u) << log_.all();
  EXPECT_EQ(calls[8], std::string("--parsable --array=1 ") + (ws() / "slurm" / "recon-tiles.sh").string());
  EXPECT_EQ(calls[9],
            std::string("--parsable --dependency=afterok:108 ") + (ws() / "slurm" / "recon-join.sh").string());
  EXPECT_EQ(calls[10], std::string("--parsable --dependency=afterok:109 ") + (ws() / "slurm" / "refine.sh").string());
  EXPECT_THAT(log_.all(), HasSubstr("recon-tiles task 1 (job 103_1) exit code 2; submitting it again"));
  const nlohmann::json record = run_json();
  EXPECT_EQ(record["stages"]["mvs"]["state"], "done");
  const auto& tasks = record["slurm"]["jobs"]["recon-tiles"]["tasks"];
  EXPECT_EQ(tasks["0"], "103_0");
  EXPECT_EQ(tasks["1"], "108_1");
  EXPECT_EQ(tasks["2"], "103_2");
  EXPECT_EQ(record["slurm"]["jobs"]["recon-join"]["tasks"]["0"], "109");
}

// From one recon job to tiles: the pending one job would still run (and
// write the mesh) unless cancelled with the jobs after it.
TEST_F(SlurmExecutorTest, ChangedTileCountCancelsTheReconJobsOfTheOtherLayout) {
  run_pipeline(options_, log_);
  set_active(kAllJobs);
  options_.assignments = {"recon.tiles=2"};
  run_pipeline(options_, log_);
  const auto calls = sbatch_calls();
  ASSERT_EQ(calls.size(), 12u) << log_.all();
  EXPECT_EQ(calls[7], std::string("--parsable --array=0,1 --dependency=afterok:102 ") +
                          (ws() / "slurm" / "recon-tiles.sh").string());
  EXPECT_EQ(calls[8],
            std::string("--parsable --dependency=afterok:107 ") + (ws() / "slurm" / "recon-join.sh").string());
  EXPECT_EQ(lines_of(fake_ / "scancel.log"),
            (std::vector<std::string>{"103", "104", "105_0 105_1 105_2 105_3", "106"}));
  EXPECT_FALSE(run_json()["slurm"]["jobs"].contains("recon"));
}

TEST_F(SlurmExecutorTest, ReRunKeepsPendingAndRunningJobs) {
  run_pipeline(options_, log_);
  set_active(kAllJobs);
  run_pipeline(options_, log_);
  EXPECT_EQ(sbatch_calls().size(), 7u) << log_.all();
  EXPECT_FALSE(fs::exists(fake_ / "scancel.log"));
}

TEST_F(SlurmExecutorTest, ChangedOptionCancelsTheStagesJobsAndSubmitsThemAgain) {
  run_pipeline(options_, log_);
  set_active(kAllJobs);
  options_.assignments = {"recon.lambda=0.5"};
  run_pipeline(options_, log_);
  const auto calls = sbatch_calls();
  ASSERT_EQ(calls.size(), 11u) << log_.all();
  EXPECT_EQ(calls[7], std::string("--parsable --dependency=afterok:102 ") + (ws() / "slurm" / "recon.sh").string());
  EXPECT_EQ(lines_of(fake_ / "scancel.log"),
            (std::vector<std::string>{"103", "104", "105_0 105_1 105_2 105_3", "106"}));
}

TEST_F(SlurmExecutorTest, InterruptCancelsEverySubmittedJob) {
  options_.executor_options = {"mvs_tasks=3", "poll_seconds=0"};
  set_active(kAllJobs);
  AlwaysCancellingReporter cancelling;
  EXPECT_THROW(run_pipeline(options_, cancelling), Cancelled);
  EXPECT_EQ(lines_of(fake_ / "scancel.log"),
            (std::vector<std::string>{"100 101_0 101_1 101_2 102 103 104 105_0 105_1 105_2 105_3 106"}));
}

TEST_F(SlurmExecutorTest, FailedTaskFailsTheRunWithItsCauseAndLogAndCancelsTheJobsAfterIt) {
  options_.executor_options = {"mvs_tasks=3", "poll_seconds=0"};
  // squeue's first call is the submission's; on the second, sfm and depth
  // task 0 have finished, task 1 rejected its input and task 2 still runs:
  // it goes on (a re-run keeps its maps), the jobs after the array stop.
  on_squeue_call(2, {"sfm=0", "mvs-depth.0=0", "mvs-depth.1=3"}, true);
  set_active({"101_2", "102", "103", "104", "105_0", "105_1", "105_2", "105_3", "106"});
  try {
    run_pipeline(options_, log_);
    FAIL() << "a failed array task did not fail the run";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr((ws() / "logs" / "mvs-depth.1.log").string()));
  }
  EXPECT_EQ(lines_of(fake_ / "scancel.log"), (std::vector<std::string>{"102 103 104 105_0 105_1 105_2 105_3 106"}));
  EXPECT_EQ(run_json()["stages"]["mvs"]["state"], "failed");
  EXPECT_EQ(run_json()["stages"]["sfm"]["state"], "done");
}

TEST_F(SlurmExecutorTest, WaitsUntilEveryJobCompletedAndCopiesTheResult) {
  options_.executor_options = {"mvs_tasks=3", "poll_seconds=0"};
  // Status files hold the exit code, the wall seconds and the CPU time as
  // `times` prints it (mvs-depth.2's as a status file without it).
  on_squeue_call(2,
                 {"sfm=0 1", "mvs-depth.0=0 5 0m4.00s 0m1.00s", "mvs-depth.1=0 9 0m8.5s 0m0.5s", "mvs-depth.2=0 4",
                  "mvs-fuse=0 2 1m0.25s 0m0.000s", "recon=0 3", "refine=0 1", "texture-views.0=0 3",
                  "texture-views.1=0 2", "texture-views.2=0 4", "texture-views.3=0 1", "texture-atlas=0 3"},
                 true);
  for (const char* file : {"mvs/points.ply", "recon/mesh.ply", "refine/mesh.ply", "texture/model.glb"}) {
    fs::create_directories((ws() / file).parent_path());
    std::ofstream(ws() / file) << "result " << file;
  }
  const DriverResult result = run_pipeline(options_, log_);
  EXPECT_EQ(read_text(options_.output), "result texture/model.glb");
  for (const auto& stage : result.stages) EXPECT_EQ(stage.state, "done") << stage.stage;
  // An array's tasks run side by side: the longest one, then the fusion.
  EXPECT_EQ(run_json()["stages"]["mvs"]["wall_seconds"], 11.0);
  EXPECT_EQ(run_json()["stages"]["texture"]["wall_seconds"], 7.0);
  // CPU time: every task's.
  EXPECT_DOUBLE_EQ(run_json()["stages"]["mvs"]["cpu_seconds"].get<double>(), 5 + 9 + 60.25);
  EXPECT_EQ(run_json()["stages"]["recon"]["cpu_seconds"], 0.0);
}

// The texture join has left the queue, but its status file shows up only at
// the next poll (a shared filesystem's cache): not a failure within the grace.
TEST_F(SlurmExecutorTest, StatusFileSeenLateWithinTheGraceIsNotAFailure) {
  options_.executor_options = {"mvs_tasks=3", "poll_seconds=0", "status_grace_seconds=60"};
  on_squeue_call(
      2,
      {"sfm=0 1", "mvs-depth.0=0 1", "mvs-depth.1=0 1", "mvs-depth.2=0 1", "mvs-fuse=0 1", "recon=0 1", "refine=0 1",
       "texture-views.0=0 1", "texture-views.1=0 1", "texture-views.2=0 1", "texture-views.3=0 1"},
      true);
  on_squeue_call(3, {"texture-atlas=0 1"}, false);
  for (const char* file : {"mvs/points.ply", "recon/mesh.ply", "refine/mesh.ply", "texture/model.glb"}) {
    fs::create_directories((ws() / file).parent_path());
    std::ofstream(ws() / file) << "result " << file;
  }
  run_pipeline(options_, log_);
  EXPECT_EQ(run_json()["stages"]["texture"]["state"], "done") << log_.all();
}

TEST_F(SlurmExecutorTest, JobGoneWithoutStatusFileAfterTheGraceIsAFailure) {
  options_.executor_options = {"mvs_tasks=3", "poll_seconds=0", "status_grace_seconds=0"};
  on_squeue_call(2, {"sfm=0 1"}, true);  // the depth tasks vanished (killed)
  EXPECT_THROW(run_pipeline(options_, log_), StageError);
  EXPECT_THAT(log_.all(), HasSubstr("mvs-depth task 0 (Slurm job 101_0) ended without a status file"));
}

TEST_F(SlurmExecutorTest, UnknownExecutorOrExecutorOptionsOfTheLocalOneAreConfigErrors) {
  options_.executor = "pbs";
  EXPECT_THROW(run_pipeline(options_, log_), ConfigError);
  options_.executor = "local";
  EXPECT_THROW(run_pipeline(options_, log_), ConfigError);  // executor_options given
  EXPECT_FALSE(fs::exists(fake_ / "sbatch.log"));
}

std::string config_error_of(const std::function<void()>& run) {
  try {
    run();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "<no ConfigError>";
}

TEST_F(SlurmExecutorTest, SlurmCommandsNotOnPathAreAConfigErrorBeforeTheWorkspace) {
  fs::remove(fake_ / "sbatch");
  // Only the fake commands: a Slurm installed on this machine must not count.
  setenv("PATH", fake_.c_str(), 1);
  const std::string message = config_error_of([&] { run_pipeline(options_, log_); });
  EXPECT_THAT(message, HasSubstr("not on PATH (missing: sbatch)"));
  EXPECT_FALSE(fs::exists(ws()));
}

TEST_F(SlurmExecutorTest, AnUnreachableControllerIsAConfigErrorBeforeTheWorkspace) {
  write_executable(fake_ / "sinfo", R"sh(#!/bin/sh
echo "sinfo: error: Unable to contact slurm controller (connect failure)" >&2
exit 1
)sh");
  const std::string message = config_error_of([&] { run_pipeline(options_, log_); });
  EXPECT_THAT(message, HasSubstr("cannot reach the Slurm controller"));
  EXPECT_THAT(message, HasSubstr("Unable to contact slurm controller"));
  EXPECT_FALSE(fs::exists(ws()));
  EXPECT_FALSE(fs::exists(fake_ / "sbatch.log"));
}

TEST(SlurmOptions, UnknownKeyAndBadValuesAreConfigErrors) {
  EXPECT_EQ(parse_slurm_options({"partition=long", "mvs_tasks=8"}).tasks_of("mvs"), 8);
  EXPECT_EQ(parse_slurm_options({"texture_tasks=6"}).tasks_of("texture"), 6);
  EXPECT_EQ(parse_slurm_options({}).tasks_of("texture"), 4);
  EXPECT_THROW(parse_slurm_options({"texture_tasks=0"}), ConfigError);
  EXPECT_THROW(parse_slurm_options({"partion=long"}), ConfigError);
  EXPECT_THROW(parse_slurm_options({"mvs_tasks=0"}), ConfigError);
  EXPECT_THROW(parse_slurm_options({"wait=maybe"}), ConfigError);
  EXPECT_THROW(parse_slurm_options({"partition"}), ConfigError);
}

TEST(SlurmOptions, ErrorsNameTheKeyAndTheAllowedValues) {
  const auto message = [](const std::string& item) {
    try {
      parse_slurm_options({item});
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("<no ConfigError>");
  };
  EXPECT_THAT(message("mvs_tasks=0"), HasSubstr("mvs_tasks"));
  EXPECT_THAT(message("mvs_tasks=0"), HasSubstr("an integer in [1, 100000]"));
  EXPECT_THAT(message("mem_mb=-1"), HasSubstr("an integer in [0, "));
  EXPECT_THAT(message("cpus=two"), HasSubstr("is not a number"));
  EXPECT_THAT(message("partion=long"), HasSubstr("did you mean partition?"));
  EXPECT_THAT(message("partion=long"), HasSubstr("status_grace_seconds, wait"));
  EXPECT_THAT(message("poll_seconds=nan"), HasSubstr("poll_seconds"));
  EXPECT_DOUBLE_EQ(parse_slurm_options({"poll_seconds=0.5"}).poll_seconds, 0.5);
  EXPECT_FALSE(parse_slurm_options({"wait=false"}).wait);
  EXPECT_EQ(parse_slurm_options({"time=1-12:00:00", "cpus=8", "mem_mb=4000"}).time, "1-12:00:00");
}

}  // namespace
}  // namespace hos::pipeline
