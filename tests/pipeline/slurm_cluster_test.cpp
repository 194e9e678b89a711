// hos-pipeline --executor slurm on a real one-node Slurm that the test starts
// (munged, slurmctld and slurmd from Debian's slurm-wlm and munge, with a
// configuration generated into a temporary folder, stopped at the end): the
// synthetic scene's .glb equals the local run's (mvs and texture split into
// array tasks of views, recon into one task per tile), and after one array
// task is killed a re-run submits only that task and what follows it. Skips
// when the daemons are not installed (scripts/install-deps.sh) or the test
// is not root (slurmd runs jobs as their user).
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "core/subprocess.h"
#include "tests/support/test_support.h"

namespace hos::pipeline {
namespace {
namespace fs = std::filesystem;
using hos::testing::read_text;
using hos::testing::run_command;
using hos::testing::shell_quote;
using ::testing::HasSubstr;
using ::testing::Not;

std::string file_bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::string short_host_name() {
  char name[256] = {};
  gethostname(name, sizeof(name) - 1);
  const std::string host = name;
  return host.substr(0, host.find('.'));
}

long memory_mb() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  long kb = 0;
  in >> key >> kb;  // "MemTotal: N kB"
  return kb / 1024;
}

// munged, slurmctld and slurmd with everything (config, keys, state, logs,
// sockets) in one folder; the daemons run in the foreground of background
// shells and are stopped by their process ids. Process tracking by the
// process list and no task plugin: no cgroups or systemd needed.
class OneNodeSlurm {
 public:
  explicit OneNodeSlurm(const fs::path& folder) : dir_(folder) {
    fs::create_directories(dir_ / "state");
    fs::create_directories(dir_ / "spool");
    fs::permissions(dir_, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                              fs::perms::others_read | fs::perms::others_exec);
    {
      std::ofstream key(dir_ / "munge.key", std::ios::binary);
      std::ifstream random("/dev/urandom", std::ios::binary);
      char bytes[1024];
      random.read(bytes, sizeof(bytes));
      key.write(bytes, sizeof(bytes));
    }
    fs::permissions(dir_ / "munge.key", fs::perms::owner_read | fs::perms::owner_write);
    const int port = 20000 + static_cast<int>(getpid() % 20000) * 2 % 20000;
    const std::string d = dir_.string();
    std::ofstream(dir_ / "slurm.conf")
        << "ClusterName=hostest\n"
        << "SlurmctldHost=" << short_host_name() << "\n"
        << "SlurmUser=root\nSlurmdUser=root\n"
        << "SlurmctldPort=" << port << "\nSlurmdPort=" << port + 1 << "\n"
        << "AuthType=auth/munge\nCredType=cred/munge\nAuthInfo=socket=" << d << "/munge.sock\n"
        << "StateSaveLocation=" << d << "/state\nSlurmdSpoolDir=" << d << "/spool\n"
        << "SlurmctldPidFile=" << d << "/slurmctld.pid\nSlurmdPidFile=" << d << "/slurmd.pid\n"
        << "SlurmctldLogFile=" << d << "/slurmctld.log\nSlurmdLogFile=" << d << "/slurmd.log\n"
        << "ProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\n"
        << "JobAcctGatherType=jobacct_gather/none\nAccountingStorageType=accounting_storage/none\n"
        << "SelectType=select/cons_tres\nSelectTypeParameters=CR_CPU\nMpiDefault=none\nReturnToService=2\n"
        << "NodeName=" << short_host_name() << " CPUs=" << std::max(1u, std::thread::hardware_concurrency())
        << " RealMemory=" << memory_mb() * 9 / 10 << " State=UNKNOWN\n"
        << "PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP\n"
        // A job whose dependency ends starts within a second, not 2-3 s
        // later: one test's chain of 8 jobs took 30 s, about 19 of them waiting.
        << "SchedulerParameters=batch_sched_delay=0,sched_min_interval=0\n";
    setenv("SLURM_CONF", (dir_ / "slurm.conf").c_str(), 1);
    if (run_command(
            "munged --key-file=" + shell_quote(d + "/munge.key") + " --socket=" + shell_quote(d + "/munge.sock") +
                " --pid-file=" + shell_quote(d + "/munged.pid") + " --log-file=" + shell_quote(d + "/munged.log") +
                " --seed-file=" + shell_quote(d + "/munge.seed") + " --force",
            dir_ / "munged.out") != 0) {
      error_ = "munged did not start: " + read_text(dir_ / "munged.out");
      return;
    }
    for (const char* daemon : {"slurmctld", "slurmd"}) {
      run_command(std::string(daemon) + " -D" + (std::string(daemon) == "slurmctld" ? " -i" : "") + " > " +
                  shell_quote(d + "/" + daemon + ".out") + " 2>&1 & echo $! > " +
                  shell_quote(d + "/" + daemon + ".shell.pid"));
    }
    for (int i = 0; i < 60; ++i) {
      run_command("sinfo --noheader --format=%T", dir_ / "sinfo.out");
      if (read_text(dir_ / "sinfo.out").find("idle") != std::string::npos) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
    }
    error_ = "the node did not become idle; slurmctld: " + read_text(dir_ / "slurmctld.out") +
             " slurmd: " + read_text(dir_ / "slurmd.out");
  }
  ~OneNodeSlurm() {
    for (const char* pid_file :
         {"slurmd.pid", "slurmd.shell.pid", "slurmctld.pid", "slurmctld.shell.pid", "munged.pid"}) {
      std::ifstream in(dir_ / pid_file);
      pid_t pid = 0;
      if (in >> pid && pid > 0) kill(pid, SIGTERM);
    }
    std::this_thread::sleep_for(std::chrono::seconds(1));
  }
  const std::string& error() const { return error_; }

 private:
  fs::path dir_;
  std::string error_;
};

class SlurmClusterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string missing = hos::testing::missing_executables(
        {"hos-pipeline", "hos-synth", "hos-sfm", "hos-mvs", "hos-recon", "hos-refine", "hos-texture"});
    if (!missing.empty()) GTEST_SKIP() << "not built:" << missing;
    for (const char* program : {"munged", "slurmctld", "slurmd", "sbatch", "squeue", "scancel", "sinfo"}) {
      if (find_executable(program).empty()) {
        GTEST_SKIP() << program << " is not installed (slurm-wlm, munge: scripts/install-deps.sh)";
      }
    }
    if (geteuid() != 0) GTEST_SKIP() << "a one-node Slurm needs root (slurmd starts jobs as their user)";
    slurm_ = std::make_unique<OneNodeSlurm>(dir_ / "slurm");
    ASSERT_TRUE(slurm_->error().empty()) << slurm_->error();
    ASSERT_EQ(hos::testing::make_synth_scene(scene_, 12, 0, dir_ / "synth.log", {320, 240}), 0)
        << read_text(dir_ / "synth.log");
  }
  void TearDown() override { slurm_.reset(); }

  // hos-pipeline on the scene with its true (PINHOLE) cameras, so sfm only
  // links the photos and both runs start from the same cameras.
  int pipeline(const fs::path& exe, const fs::path& out, const std::string& extra, const std::string& log) {
    return run_command(shell_quote(exe.string()) + " " + shell_quote((scene_ / "images").string()) + " " +
                           shell_quote(out.string()) + " --sparse " + shell_quote((scene_ / "sparse").string()) +
                           " --preset fast --progress none " + extra,
                       dir_ / log);
  }
  std::string log(const std::string& name) const { return read_text(dir_ / name); }

  hos::testing::TempDir dir_{"hos-slurm-cluster"};
  fs::path scene_ = dir_.path() / "scene";
  std::unique_ptr<OneNodeSlurm> slurm_;
  static constexpr const char* kSlurm =
      "--executor slurm --executor-option mvs_tasks=3 --executor-option texture_tasks=3 "
      "--executor-option poll_seconds=1";
};

TEST_F(SlurmClusterTest, SyntheticSceneThroughSlurmEqualsTheLocalRun) {
  const fs::path exe = hos::testing::executable("hos-pipeline");
  // Both runs reconstruct in 2 tiles: locally one after the other in one
  // process, on Slurm as a 2-task array and a join.
  const std::string tiles = "--set recon.tiles=2 ";
  ASSERT_EQ(pipeline(exe, dir_ / "local.glb", tiles, "local.log"), 0) << log("local.log");
  ASSERT_EQ(pipeline(exe, dir_ / "slurm.glb", tiles + kSlurm, "slurm.log"), 0) << log("slurm.log");
  const fs::path ws = dir_ / "slurm_workspace", local_ws = dir_ / "local_workspace";
  // mvs and texture ran as 3 array tasks of 4 views each, then the fusion
  // and the atlas; recon as one task per tile, then the join.
  const nlohmann::json record = nlohmann::json::parse(read_text(ws / "run.json"));
  for (const std::string job : {"mvs-depth", "texture-views"}) {
    EXPECT_EQ(record["slurm"]["jobs"][job]["tasks"].size(), 3u) << job;
    for (int task = 0; task < 3; ++task) {
      EXPECT_THAT(read_text(ws / "logs" / (job + "." + std::to_string(task) + ".log")), HasSubstr(": 4 of 12 views"))
          << job << " task " << task;
    }
  }
  ASSERT_TRUE(record["slurm"]["jobs"].contains("recon-tiles")) << "recon was not submitted as an array of tiles";
  EXPECT_EQ(record["slurm"]["jobs"]["recon-tiles"]["tasks"].size(), 2u);
  for (int task = 0; task < 2; ++task) {
    EXPECT_THAT(read_text(ws / "logs" / ("recon-tiles." + std::to_string(task) + ".log")),
                HasSubstr("recon: tile " + std::to_string(task) + " of 2: "))
        << "recon tile " << task;
  }
  EXPECT_THAT(read_text(ws / "logs" / "recon.log"), HasSubstr("recon: joined 2 tiles"));
  EXPECT_THAT(read_text(local_ws / "logs" / "recon.log"), HasSubstr("grid in 2 tiles (recon.tiles)"));
  EXPECT_FALSE(record["slurm"]["jobs"].contains("recon"));
  for (const char* job : {"recon-join", "texture-atlas"}) {
    EXPECT_EQ(record["slurm"]["jobs"][job]["tasks"].size(), 1u) << job;
  }
  for (const auto& [stage, entry] : record["stages"].items()) EXPECT_EQ(entry["state"], "done") << stage;
  EXPECT_TRUE(file_bytes(ws / "mvs" / "points.ply") == file_bytes(local_ws / "mvs" / "points.ply"));
  EXPECT_TRUE(file_bytes(ws / "recon" / "mesh.ply") == file_bytes(local_ws / "recon" / "mesh.ply"));
  const std::string local = file_bytes(dir_ / "local.glb");
  ASSERT_FALSE(local.empty());
  EXPECT_TRUE(file_bytes(dir_ / "slurm.glb") == local) << "the Slurm run's .glb differs from the local run's";
}

TEST_F(SlurmClusterTest, ReRunAfterAKilledArrayTaskSubmitsOnlyThatTaskAndWhatFollows) {
  // hos-pipeline takes its stages from its own folder: a copy beside a
  // hos-mvs that has Slurm kill its own array task (views 4-7) the first time.
  const fs::path bin = dir_ / "bin";
  fs::create_directories(bin);
  fs::copy_file(hos::testing::executable("hos-pipeline"), bin / "hos-pipeline");
  for (const char* stage : {"hos-sfm", "hos-recon", "hos-refine", "hos-texture"}) {
    fs::create_symlink(hos::testing::executable(stage), bin / stage);
  }
  const fs::path killed = dir_ / "killed_once";
  std::ofstream(bin / "hos-mvs") << "#!/bin/sh\n"
                                 << "case \" $* \" in *\" --views 4-7 \"*)\n"
                                 << "  if [ ! -e " << shell_quote(killed.string()) << " ]; then\n"
                                 << "    touch " << shell_quote(killed.string()) << "\n"
                                 << "    scancel \"${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}\"; sleep 60\n"
                                 << "  fi;;\n"
                                 << "esac\n"
                                 << "exec " << shell_quote(hos::testing::executable("hos-mvs").string()) << " \"$@\"\n";
  fs::permissions(bin / "hos-mvs", fs::perms::owner_all);

  const fs::path out = dir_ / "out.glb", ws = dir_ / "out_workspace";
  EXPECT_NE(pipeline(bin / "hos-pipeline", out, kSlurm, "run1.log"), 0) << log("run1.log");
  ASSERT_TRUE(fs::exists(killed)) << log("run1.log");
  EXPECT_THAT(log("run1.log"), HasSubstr("mvs-depth task 1"));
  const nlohmann::json first = nlohmann::json::parse(read_text(ws / "run.json"));
  EXPECT_EQ(first["stages"]["sfm"]["state"], "done");
  EXPECT_EQ(first["stages"]["mvs"]["state"], "failed");

  ASSERT_EQ(pipeline(bin / "hos-pipeline", out, kSlurm, "run2.log"), 0) << log("run2.log");
  const std::string run2 = log("run2.log");
  EXPECT_THAT(run2, Not(HasSubstr("submitted sfm")));
  EXPECT_THAT(run2, HasSubstr("sfm: up to date"));
  EXPECT_THAT(run2, HasSubstr("submitted mvs-depth as Slurm job"));
  EXPECT_THAT(run2, HasSubstr(" tasks 1\n"));
  EXPECT_THAT(run2, HasSubstr("submitted mvs-fuse"));
  const nlohmann::json second = nlohmann::json::parse(read_text(ws / "run.json"));
  const auto& before = first["slurm"]["jobs"]["mvs-depth"]["tasks"];
  const auto& after = second["slurm"]["jobs"]["mvs-depth"]["tasks"];
  EXPECT_EQ(after["0"], before["0"]);
  EXPECT_EQ(after["2"], before["2"]);
  EXPECT_NE(after["1"], before["1"]);
  EXPECT_EQ(second["slurm"]["jobs"]["sfm"], first["slurm"]["jobs"]["sfm"]);
  for (const auto& [stage, entry] : second["stages"].items()) EXPECT_EQ(entry["state"], "done") << stage;
  EXPECT_GT(fs::file_size(out), 1000u);
}

}  // namespace
}  // namespace hos::pipeline
