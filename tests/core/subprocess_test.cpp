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
