// WS/mvs/report.json: what hos-mvs writes the pipeline reads back field by
// field, and a missing or damaged file is an InputError naming it.
#include "mvs/mvs_report.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "core/json_report.h"
#include "tests/support/damaged_file_checks.h"
#include "tests/support/test_support.h"

namespace hos::mvs {
namespace {

MvsReport example_report() {
  MvsReport r;
  r.views = 3;
  r.views_skipped = 1;
  r.points = 123456789012;
  r.seconds_depth = 12.5;
  r.seconds_fusion = 0.125;
  r.per_view = {{"a/view_000.png", 4, false, 76800, 51200, 2.0 / 3.0, 1.25},
                {"view_001.png", 0, true, 0, 0, 0.0, 0.0},
                {"view_002.png", 2, false, 100, 1, 0.01, 0.5}};
  r.confidence = {2.0, 7.0, {0, 5, 9, 1, 2}};
  return r;
}

TEST(MvsReport, ReadsBackWhatItWrites) {
  hos::testing::TempDir dir;
  const MvsReport written = example_report();
  write_json_report(dir / "report.json", to_json(written));
  const MvsReport read = read_mvs_report(dir / "report.json");
  EXPECT_EQ(read.views, 3);
  EXPECT_EQ(read.views_skipped, 1);
  EXPECT_EQ(read.points, 123456789012);
  EXPECT_EQ(read.seconds_depth, 12.5);
  EXPECT_EQ(read.seconds_fusion, 0.125);
  ASSERT_EQ(read.per_view.size(), written.per_view.size());
  for (std::size_t i = 0; i < written.per_view.size(); ++i) {
    const MvsViewReport &w = written.per_view[i], &r = read.per_view[i];
    EXPECT_EQ(r.name, w.name);
    EXPECT_EQ(r.sources, w.sources);
    EXPECT_EQ(r.skipped, w.skipped);
    EXPECT_EQ(r.pixels, w.pixels);
    EXPECT_EQ(r.valid_pixels, w.valid_pixels);
    EXPECT_EQ(r.coverage, w.coverage);  // exactly: JSON keeps every digit a double needs
    EXPECT_EQ(r.seconds, w.seconds);
  }
  EXPECT_EQ(read.confidence.lo, 2.0);
  EXPECT_EQ(read.confidence.hi, 7.0);
  EXPECT_EQ(read.confidence.counts, written.confidence.counts);
  // And the same file again.
  EXPECT_EQ(to_json(read).dump(), to_json(written).dump());
}

TEST(MvsReport, AMissingOrMalformedReportIsAnInputErrorNamingTheFile) {
  hos::testing::expect_input_error_naming_the_file(
      "report.json", [](const std::filesystem::path& file) { read_mvs_report(file); },
      {"", R"({"views": 3,)", "[1, 2]", R"({"per_view": 3})", R"({"per_view": [{"name": 7}]})", R"({"points": "many"})",
       R"({"confidence": {"lo": "x"}})"});
}

}  // namespace
}  // namespace hos::mvs
