// core/reporter.*: the plain and JSON progress formats and the log file.
#include "core/reporter.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "core/error.h"
#include "tests/support/test_support.h"

namespace hos {
namespace {

TEST(Reporter, JsonLinesCarryStageStepAndCounts) {
  std::ostringstream out;
  ConsoleReporterOptions options;
  options.stage = "mvs";
  options.style = ProgressStyle::kJson;
  options.plain_interval_s = 0.0;
  {
    ConsoleReporter r(options, &out);
    r.begin("depth maps", 4);
    r.advance(2);
    r.advance(2);
    r.end();
  }
  const std::string s = out.str();
  EXPECT_NE(s.find("\"stage\":\"mvs\""), std::string::npos) << s;
  EXPECT_NE(s.find("\"step\":\"depth maps\""), std::string::npos) << s;
  EXPECT_NE(s.find("\"done\":4"), std::string::npos) << s;
  EXPECT_NE(s.find("\"total\":4"), std::string::npos) << s;
}

TEST(Reporter, PlainLinesAndLogFile) {
  hos::testing::TempDir dir;
  std::ostringstream out;
  ConsoleReporterOptions options;
  options.stage = "recon";
  options.style = ProgressStyle::kPlain;
  options.plain_interval_s = 0.0;
  {
    ConsoleReporter r(options, &out);
    r.open_log_file((dir / "log.txt").string());
    r.begin("solve", 10);
    r.advance(10);
    r.end();
    r.debug("residual 1e-7");
    r.warn("something odd");
  }
  EXPECT_NE(out.str().find("recon"), std::string::npos);
  EXPECT_NE(out.str().find("10/10"), std::string::npos) << out.str();
  EXPECT_EQ(out.str().find("residual 1e-7"), std::string::npos) << "debug stays off the terminal";
  std::ifstream log(dir / "log.txt");
  const std::string logged((std::istreambuf_iterator<char>(log)), {});
  EXPECT_NE(logged.find("residual 1e-7"), std::string::npos) << "the log file gets every level";
  EXPECT_NE(logged.find("something odd"), std::string::npos);
}

TEST(Reporter, CancellationThrows) {
  ConsoleReporterOptions options;
  options.style = ProgressStyle::kNone;
  options.cancel_requested = [] { return true; };
  std::ostringstream out;
  ConsoleReporter r(options, &out);
  EXPECT_THROW(r.throw_if_cancelled(), Error);
}

}  // namespace
}  // namespace hos
