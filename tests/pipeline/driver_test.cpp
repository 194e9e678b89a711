// The driver's resume logic, exit-code mapping and interruption, with small
// shell scripts standing in for the stage executables (the real stages are
// exercised by the end-to-end tests).
#include "pipeline/driver.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "core/error.h"
#include "pipeline/output_checks.h"
#include "pipeline/pipeline_config.h"
#include "pipeline/workspace_lock.h"
#include "tests/support/message_log.h"
#include "tests/support/test_support.h"

namespace hos::pipeline {
namespace {
namespace fs = std::filesystem;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

// Each fake appends its name to $HOS_FAKE_CALLS, fails with $HOS_FAKE_EXIT if
// $HOS_FAKE_FAIL names it, sleeps if $HOS_FAKE_SLEEP names it, burns CPU in
// a child of its own if $HOS_FAKE_BURN names it, and writes its
// output (content derived from its input so changes propagate).
constexpr const char* kFakeStage = R"(#!/bin/sh
stage="$1"; shift
out=""; ws=""; input=""
while [ $# -gt 0 ]; do
  case "$1" in
    --output) out="$2"; shift ;;
    --workspace) ws="$2"; shift ;;
    --input|--mesh) input="$2"; shift ;;
  esac
  shift
done
echo "$stage" >> "$HOS_FAKE_CALLS"
if [ "$HOS_FAKE_SLEEP" = "$stage" ]; then echo $$ > "$HOS_FAKE_CALLS.pid"; exec sleep 30; fi
if [ "$HOS_FAKE_FAIL" = "$stage" ]; then echo "$stage: failing on purpose" >&2; exit "$HOS_FAKE_EXIT"; fi
if [ "$HOS_FAKE_BURN" = "$stage" ]; then sh -c 'i=0; while [ $i -lt 200000 ]; do i=$((i + 1)); done'; fi
case "$stage" in
  sfm)
    mkdir -p "$ws/sfm/undistorted/sparse" "$ws/sfm/undistorted/images"
    ls "$HOS_FAKE_PHOTOS" > "$ws/sfm/undistorted/sparse/cameras.txt"
    echo '{"images_registered": 3, "images_given": 4, "points": 42}' > "$ws/sfm/report.json" ;;
  mvs)
    printf 'ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nend_header\n1\n2\n' > "$out.tmp"
    cat "$ws/sparse/cameras.txt" >> "$out.tmp"; mv "$out.tmp" "$out" ;;
  recon|refine)
    printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nelement face 1\nend_header\n' > "$out" ;;
  texture)
    echo "glb from $input" > "$out" ;;
esac
)";

// A file the sfm stage's fingerprint counts as a photo: JPEG's first bytes
// (the fingerprint recognises photos by content), then a tag that makes
// each one different.
void write_fake_photo(const fs::path& file, const std::string& tag) {
  std::ofstream(file, std::ios::binary) << "\xFF\xD8\xFF\xE0" << tag;
}

class DriverTest : public ::testing::Test {
 protected:
  void SetUp() override {
    bin_ = dir_ / "bin";
    fs::create_directories(bin_);
    fs::create_directories(dir_ / "photos");
    for (const char* name : {"a.jpg", "b.jpg", "c.jpg", "d.jpg"}) write_fake_photo(dir_ / "photos" / name, name);
    std::ofstream(bin_ / "fake-stage") << kFakeStage;
    ::chmod((bin_ / "fake-stage").c_str(), 0755);
    for (const char* stage : {"sfm", "mvs", "recon", "refine", "texture"}) {
      const fs::path exe = bin_ / (std::string("hos-") + stage);
      std::ofstream(exe) << "#!/bin/sh\nexec \"$(dirname \"$0\")/fake-stage\" " << stage << " \"$@\"\n";
      ::chmod(exe.c_str(), 0755);
    }
    ::setenv("HOS_FAKE_CALLS", (dir_ / "calls.txt").c_str(), 1);
    ::setenv("HOS_FAKE_PHOTOS", (dir_ / "photos").c_str(), 1);
    ::unsetenv("HOS_FAKE_FAIL");
    ::unsetenv("HOS_FAKE_SLEEP");
    ::unsetenv("HOS_FAKE_BURN");
    options_.photos = dir_ / "photos";
    options_.output = dir_ / "out.glb";
    options_.bin_dir = bin_;
    options_.progress = "none";
  }

  // Runs the driver; returns the stages that ran (from the fakes' call log).
  std::vector<std::string> run(Reporter& reporter = null_reporter()) {
    fs::remove(dir_ / "calls.txt");
    run_pipeline(options_, reporter);
    return calls();
  }
  std::vector<std::string> calls() const {
    std::vector<std::string> out;
    std::ifstream in(dir_ / "calls.txt");
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
  }
  fs::path workspace() const { return dir_ / "out_workspace"; }

  hos::testing::TempDir dir_;
  fs::path bin_;
  DriverOptions options_;
};

TEST_F(DriverTest, FirstRunRunsEverythingAndCopiesTheResult) {
  EXPECT_THAT(run(), ElementsAre("sfm", "mvs", "recon", "refine", "texture"));
  ASSERT_TRUE(fs::exists(options_.output));
  std::ifstream in(options_.output);
  std::string text;
  std::getline(in, text);
  EXPECT_THAT(text, HasSubstr("mesh.ply"));
  EXPECT_TRUE(fs::exists(workspace() / "config.yaml"));
  const RunRecord record = load_run_record(workspace() / "run.json");
  ASSERT_EQ(record.stages.size(), 5u);
  EXPECT_EQ(record.stages.at("texture").state, "done");
  EXPECT_EQ(record.stages.at("sfm").figures.value("images_registered", 0), 3);
  EXPECT_EQ(record.stages.at("mvs").figures.value("points", 0), 2);
  EXPECT_EQ(record.stages.at("recon").figures.value("faces", 0), 1);
}

TEST_F(DriverTest, SecondRunSkipsEverything) {
  run();
  EXPECT_TRUE(run().empty());
}

TEST_F(DriverTest, DeletedTextureOutputRerunsOnlyTexture) {
  run();
  fs::remove(workspace() / "texture" / "model.glb");
  EXPECT_THAT(run(), ElementsAre("texture"));
}

TEST_F(DriverTest, DeletedDensePointsRerunFromMvs) {
  run();
  fs::remove(workspace() / "mvs" / "points.ply");
  EXPECT_THAT(run(), ElementsAre("mvs", "recon", "refine", "texture"));
}

TEST_F(DriverTest, ChangedOptionRerunsThatStageAndLaterOnes) {
  run();
  options_.assignments = {"sfm.max_num_features=5000"};
  EXPECT_THAT(run(), ElementsAre("sfm", "mvs", "recon", "refine", "texture"));
  EXPECT_TRUE(run().empty());
}

TEST_F(DriverTest, ChangedReconLambdaRerunsReconAndTextureOnly) {
  if (!PipelineConfig().has_stage("recon")) GTEST_SKIP() << "the recon stage is not part of this build";
  run();
  options_.assignments = {"recon.lambda=0.25"};
  EXPECT_THAT(run(), ElementsAre("recon", "refine", "texture"));
  EXPECT_TRUE(run().empty());
}

TEST_F(DriverTest, ChangedPhotosRerunEverything) {
  run();
  write_fake_photo(dir_ / "photos" / "e.jpg", "e");
  EXPECT_THAT(run(), ElementsAre("sfm", "mvs", "recon", "refine", "texture"));
}

TEST_F(DriverTest, FromToAndForce) {
  options_.to = "mvs";
  EXPECT_THAT(run(), ElementsAre("sfm", "mvs"));
  EXPECT_FALSE(fs::exists(options_.output));
  options_.to.clear();
  options_.from = "recon";
  EXPECT_THAT(run(), ElementsAre("recon", "refine", "texture"));
  options_.from.clear();
  options_.force = true;
  EXPECT_THAT(run(), ElementsAre("sfm", "mvs", "recon", "refine", "texture"));
}

TEST_F(DriverTest, FromNeedsEarlierResults) {
  options_.from = "recon";
  EXPECT_THROW(run(), InputError);
  EXPECT_TRUE(calls().empty());
}

TEST_F(DriverTest, FailedStageKeepsItsExitCauseAndResumesThere) {
  ::setenv("HOS_FAKE_FAIL", "mvs", 1);
  ::setenv("HOS_FAKE_EXIT", "3", 1);
  try {
    run();
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("mvs.log"));
  }
  EXPECT_EQ(load_run_record(workspace() / "run.json").stages.at("mvs").state, "failed");
  EXPECT_FALSE(fs::exists(options_.output));
  ::setenv("HOS_FAKE_EXIT", "4", 1);
  EXPECT_THROW(run(), StageError);
  ::unsetenv("HOS_FAKE_FAIL");
  EXPECT_THAT(run(), ElementsAre("mvs", "recon", "refine", "texture"));
}

TEST_F(DriverTest, MissingStageExecutableIsNamedBeforeAnythingRuns) {
  fs::remove(bin_ / "hos-texture");
  try {
    run();
    FAIL() << "no error";
  } catch (const StageError& e) {
    EXPECT_THAT(e.what(), HasSubstr("hos-texture is not built"));
  }
  EXPECT_TRUE(calls().empty());
  options_.to = "recon";
  EXPECT_THAT(run(), ElementsAre("sfm", "mvs", "recon"));
}

class CancellingReporter : public Reporter {
 public:
  bool cancel_requested() const override { return cancel.load(); }
  std::atomic<bool> cancel{false};
};

TEST_F(DriverTest, InterruptStopsTheStageAndTheNextRunResumes) {
  ::setenv("HOS_FAKE_SLEEP", "mvs", 1);
  CancellingReporter reporter;
  std::thread interrupter([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    reporter.cancel = true;
  });
  EXPECT_THROW(run(reporter), Cancelled);
  interrupter.join();
  EXPECT_EQ(load_run_record(workspace() / "run.json").stages.at("mvs").state, "interrupted");
  EXPECT_FALSE(fs::exists(workspace() / "mvs" / "points.ply"));
  ::unsetenv("HOS_FAKE_SLEEP");
  EXPECT_THAT(run(), ElementsAre("mvs", "recon", "refine", "texture"));
}

TEST_F(DriverTest, BadInvocations) {
  DriverOptions bad = options_;
  bad.photos = dir_ / "missing";
  EXPECT_THROW(run_pipeline(bad, null_reporter()), InputError);
  bad = options_;
  bad.output = dir_ / "missing" / "out.glb";
  EXPECT_THROW(run_pipeline(bad, null_reporter()), OutputError);
  EXPECT_FALSE(fs::exists(dir_ / "missing"));
  bad = options_;
  bad.output = dir_ / "out.fbx";
  EXPECT_THROW(run_pipeline(bad, null_reporter()), ConfigError);
  bad = options_;
  bad.preset = "turbo";
  EXPECT_THROW(run_pipeline(bad, null_reporter()), ConfigError);
  bad = options_;
  bad.assignments = {"sfm.no_such_key=1"};
  EXPECT_THROW(run_pipeline(bad, null_reporter()), ConfigError);
  bad = options_;
  bad.from = "meshing";
  EXPECT_THROW(run_pipeline(bad, null_reporter()), ConfigError);
  EXPECT_TRUE(calls().empty());
}

TEST_F(DriverTest, SummaryTableListsEveryStage) {
  run_pipeline(options_, null_reporter());
  const DriverResult result = run_pipeline(options_, null_reporter());
  const auto lines = summary_table(result);
  ASSERT_GE(lines.size(), 6u);
  EXPECT_THAT(lines[1], HasSubstr("sfm"));
  EXPECT_THAT(lines[1], HasSubstr("up to date"));
  EXPECT_THAT(lines[1], HasSubstr("3/4 images registered"));
  EXPECT_THAT(lines.back(), HasSubstr("out.glb"));
}

// A stage's CPU time counts its children too, and never exceeds what the
// cores could give in its wall time.
TEST_F(DriverTest, RunRecordHoldsEachStagesCpuTimeBesideItsWallTime) {
  ::setenv("HOS_FAKE_BURN", "mvs", 1);
  const DriverResult result = run_pipeline(options_, null_reporter());
  ::unsetenv("HOS_FAKE_BURN");
  const nlohmann::json stages = nlohmann::json::parse(testing::read_text(workspace() / "run.json"))["stages"];
  const double cores = std::thread::hardware_concurrency();
  const double mvs_cpu = stages["mvs"]["cpu_seconds"], mvs_wall = stages["mvs"]["wall_seconds"];
  EXPECT_GT(mvs_cpu, 0.05);
  EXPECT_LE(mvs_cpu, mvs_wall * cores + 0.05);
  EXPECT_LT(stages["recon"]["cpu_seconds"].get<double>(), mvs_cpu) << "recon burns nothing";
  const auto lines = summary_table(result);
  EXPECT_THAT(lines[0], HasSubstr("time       cpu"));
  std::ostringstream cpu;
  cpu << std::fixed << std::setprecision(1) << mvs_cpu << " s";
  EXPECT_THAT(lines[2], HasSubstr(cpu.str()));
}

// ---- reliability (issue #14) -------------------------------------------------

// Waits until file exists and is not empty (the fake stage has started).
bool wait_for_file(const fs::path& file, double seconds) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < until) {
    if (!testing::read_text(file).empty()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

// A process that exited (or a zombie waiting for its reaper) is gone.
bool process_gone(pid_t pid) {
  if (::kill(pid, 0) != 0) return true;
  const std::string stat = testing::read_text("/proc/" + std::to_string(pid) + "/stat");
  const auto paren = stat.rfind(')');
  return paren != std::string::npos && paren + 2 < stat.size() && stat[paren + 2] == 'Z';
}

TEST_F(DriverTest, SecondRunOnTheSameWorkspaceIsRefusedNamingTheFirst) {
  ::setenv("HOS_FAKE_SLEEP", "sfm", 1);
  CancellingReporter first_reporter;
  std::thread first([&] { EXPECT_THROW(run_pipeline(options_, first_reporter), Cancelled); });
  const bool started = wait_for_file(dir_ / "calls.txt.pid", 10.0);
  try {
    run_pipeline(options_, null_reporter());
    ADD_FAILURE() << "the second run was not refused";
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.what(), HasSubstr("in use by another hos-pipeline (pid " + std::to_string(::getpid()) + ")"));
  }
  first_reporter.cancel = true;
  first.join();
  EXPECT_TRUE(started);
  EXPECT_EQ(calls(), std::vector<std::string>{"sfm"});  // the second run started nothing
}

TEST_F(DriverTest, LockOfAKilledRunIsTakenOverWithAWarning) {
  fs::create_directories(workspace());
  std::ofstream(WorkspaceLock::file_in(workspace())) << "pid 999999";  // no flock: its owner died
  testing::MessageLog log;
  EXPECT_THAT(run(log), ElementsAre("sfm", "mvs", "recon", "refine", "texture"));
  EXPECT_THAT(log.warnings(), HasSubstr("taking over the workspace lock"));
  EXPECT_THAT(log.warnings(), HasSubstr("pid 999999"));
  EXPECT_TRUE(testing::read_text(WorkspaceLock::file_in(workspace())).empty());  // released cleanly
}

TEST_F(DriverTest, KilledDriverLeavesNoOrphanStage) {
  ::setenv("HOS_FAKE_SLEEP", "mvs", 1);
  const pid_t driver = ::fork();
  ASSERT_GE(driver, 0);
  if (driver == 0) {
    try {
      run_pipeline(options_, null_reporter());
    } catch (...) {
    }
    ::_exit(0);
  }
  ASSERT_TRUE(wait_for_file(dir_ / "calls.txt.pid", 20.0));
  const pid_t stage = std::stoi(testing::read_text(dir_ / "calls.txt.pid"));
  ::kill(driver, SIGKILL);
  ::waitpid(driver, nullptr, 0);
  bool gone = false;
  for (int i = 0; i < 150 && !(gone = process_gone(stage)); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (!gone) ::kill(stage, SIGKILL);
  EXPECT_TRUE(gone) << "the stage (pid " << stage << ") outlived the killed driver";
}

TEST_F(DriverTest, UnwritableOutputIsRefusedBeforeTheFirstStage) {
  // A folder no file can be created in, even by root: a read-only
  // pseudo-filesystem stands in for a read-only folder.
  options_.output = "/proc/hos-test-out.glb";
  options_.workspace = dir_ / "ws";
  try {
    run();
    FAIL() << "no error";
  } catch (const OutputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("cannot create a file in /proc"));
  }
  EXPECT_TRUE(calls().empty());
}

TEST_F(DriverTest, FailedFinalCopyIsAnOutputErrorWithTheReason) {
  // The model is a folder: copying it fails as a full disk would, after
  // the temporary was created.
  fs::create_directories(dir_ / "model_folder.glb");
  try {
    copy_result(dir_ / "model_folder.glb", dir_ / "final.glb");
    FAIL() << "no error";
  } catch (const OutputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("final.glb"));
    EXPECT_THAT(e.what(), HasSubstr("the disk mounted at"));
  }
  EXPECT_FALSE(fs::exists(dir_ / "final.glb"));
}

TEST_F(DriverTest, LowDiskSpaceIsWarnedBeforeTheStage) {
  testing::MessageLog log;
  warn_if_low_space(dir_.path(), std::uintmax_t{1} << 62, "mvs", log);
  EXPECT_THAT(log.warnings(), HasSubstr("the mvs stage may need about"));
  EXPECT_THAT(log.warnings(), HasSubstr("the disk mounted at"));
  testing::MessageLog quiet;
  warn_if_low_space(dir_.path(), 1, "mvs", quiet);
  EXPECT_TRUE(quiet.warnings().empty());
}

TEST_F(DriverTest, OutputInsideThePhotoFolderStillResumes) {
  options_.output = options_.photos / "model.glb";
  EXPECT_THAT(run(), ElementsAre("sfm", "mvs", "recon", "refine", "texture"));
  EXPECT_TRUE(run().empty());
  write_fake_photo(options_.photos / "e.jpg", "e");  // a real new photo still counts
  EXPECT_THAT(run(), ElementsAre("sfm", "mvs", "recon", "refine", "texture"));
}

TEST_F(DriverTest, DamagedIntermediateNamesForceFrom) {
  run();
  std::ofstream(workspace() / "mvs" / "points.ply") << "damaged";
  ::setenv("HOS_FAKE_FAIL", "recon", 1);  // the stage rejects the damaged file
  ::setenv("HOS_FAKE_EXIT", "3", 1);
  try {
    run();
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("--force --from mvs"));
  }
}

TEST_F(DriverTest, FromWithoutAWorkspaceCreatesNone) {
  options_.from = "recon";
  EXPECT_THROW(run(), InputError);
  EXPECT_FALSE(fs::exists(workspace()));
}

}  // namespace
}  // namespace hos::pipeline
