#include "core/subprocess.h"

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "core/error.h"
#include "core/reporter.h"

namespace hos {
namespace {

TEST(Subprocess, CapturesLinesAndExitCode) {
  ProcessOptions options;
  options.argv = {"sh", "-c", "echo one; echo two >&2; printf 'three\\rfour'; exit 3"};
  std::vector<std::string> lines;
  options.on_line = [&](std::string_view line) { lines.emplace_back(line); };
  const ProcessResult result = run_process(options);
  EXPECT_EQ(result.exit_code, 3);
  EXPECT_FALSE(result.ok());
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], "one");
  EXPECT_EQ(lines[3], "four");
  EXPECT_GT(result.peak_rss_bytes, 0);
}

TEST(Subprocess, EnvironmentIsPassed) {
  ProcessOptions options;
  options.argv = {"sh", "-c", "echo \"$HOS_TEST_VALUE\""};
  options.environment = {{"HOS_TEST_VALUE", "x y"}};
  std::string out;
  options.on_line = [&](std::string_view line) { out += line; };
  EXPECT_TRUE(run_process(options).ok());
  EXPECT_EQ(out, "x y");
}

TEST(Subprocess, MissingProgramIsStageErrorNamingIt) {
  ProcessOptions options;
  options.argv = {"hos-no-such-program-xyz"};
  try {
    run_process(options);
    FAIL() << "no error";
  } catch (const StageError& e) {
    EXPECT_NE(std::string(e.what()).find("hos-no-such-program-xyz"), std::string::npos);
  }
  EXPECT_TRUE(find_executable("hos-no-such-program-xyz").empty());
  EXPECT_FALSE(find_executable("sh").empty());
}

// CPU time counts the child and what it waited for, and never more than
// its cores could give in its wall time.
TEST(Subprocess, CpuTimeOfTheChildAndItsChildren) {
  ProcessOptions options;
  // The work runs in a grandchild: only a count that includes the processes
  // the child waited for sees it.
  options.argv = {"sh", "-c", "sh -c 'i=0; while [ $i -lt 200000 ]; do i=$((i + 1)); done'"};
  const ProcessResult result = run_process(options);
  ASSERT_TRUE(result.ok());
  EXPECT_GT(result.cpu_seconds, 0.05);
  const double cores = std::thread::hardware_concurrency();
  EXPECT_LE(result.cpu_seconds, result.wall_seconds * cores + 0.05);

  options.argv = {"sleep", "0.3"};
  const ProcessResult idle = run_process(options);
  EXPECT_GE(idle.wall_seconds, 0.3);
  EXPECT_LT(idle.cpu_seconds, 0.1) << "sleeping costs no CPU";
}

class FlagReporter : public Reporter {
 public:
  bool cancel_requested() const override { return flag.load(); }
  std::atomic<bool> flag{false};
};

TEST(Subprocess, CancellationStopsTheChild) {
  FlagReporter reporter;
  ProcessOptions options;
  options.argv = {"sleep", "30"};
  options.cancel_source = &reporter;
  std::thread canceller([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    reporter.flag = true;
  });
  const ProcessResult result = run_process(options);
  canceller.join();
  EXPECT_TRUE(result.cancelled);
  EXPECT_EQ(result.signal, SIGTERM);
  EXPECT_LT(result.wall_seconds, 20.0);
}

}  // namespace
}  // namespace hos
