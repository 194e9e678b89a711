#include "pipeline/report.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/colmap_io.h"
#include "core/error.h"
#include "core/ply_io.h"
#include "pipeline/run_record.h"
#include "pipeline/stage_paths.h"
#include "pipeline/svg_plot.h"
#include "tests/support/test_support.h"

namespace hos::pipeline {
namespace {
namespace fs = std::filesystem;

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Two photos seeing three points (tracks of 2), one unregistered photo, one
// skipped file, 100 dense points with confidence 2..5.
void write_stage_outputs(const StagePaths& paths) {
  SparseModel model;
  Camera camera;
  camera.id = 1;
  camera.width = 64;
  camera.height = 48;
  camera.params = {50.0, 50.0, 32.0, 24.0};
  model.cameras[1] = camera;
  for (int i = 1; i <= 2; ++i) {
    ImageRecord image;
    image.id = i;
    image.camera_id = 1;
    image.name = "view_00" + std::to_string(i) + ".png";
    image.keypoints.resize(3);
    model.images[i] = image;
  }
  for (int p = 0; p < 3; ++p) {
    Point3D point;
    point.id = p + 1;
    point.error = 0.25 * (p + 1);
    point.track = {{1, p}, {2, p}};
    model.points[point.id] = point;
    for (int i = 1; i <= 2; ++i) model.images[i].keypoints[std::size_t(p)].point3d_id = point.id;
  }
  write_colmap_model(model, paths.undistorted / "sparse", ColmapFormat::kBinary);
  fs::create_directories(paths.undistorted / "images");
  for (const auto& image : model.images) std::ofstream(paths.undistorted / "images" / image.second.name) << "x";
  std::ofstream(paths.sfm_report) << R"({"images_given": 3, "images_registered": 2, "unregistered": ["view_003.png"],
    "skipped": [{"file": "notes.txt", "reason": "not an image"}]})";

  PointCloud cloud;
  for (int i = 0; i < 100; ++i) {
    cloud.positions.emplace_back(float(i), 0.0f, 0.0f);
    cloud.confidence.push_back(float(2 + i % 4));
  }
  fs::create_directories(paths.points.parent_path());
  write_point_cloud_ply(paths.points, cloud);
  fs::create_directories(paths.logs);
  std::ofstream(paths.log("texture"))
      << "[texture] info: start\n[texture] warning: 3 of 9 faces are seen by no photo\n";
  std::ofstream(paths.config) << "recon:\n  lambda: 0.2\n";
}

RunRecord record_with(const std::vector<std::pair<std::string, std::string>>& states) {
  RunRecord record;
  record.photos = "photos";
  record.output = "out.glb";
  for (const auto& [stage, state] : states) {
    StageRecord& s = record.stages[stage];
    s.state = state;
    s.wall_seconds = 1.5;
    s.peak_memory_bytes = 64 << 20;
    s.exit_code = state == "failed" ? 5 : 0;
  }
  return record;
}

TEST(RunReport, FinishedRunHasEveryTableAndPlot) {
  hos::testing::TempDir dir;
  const StagePaths paths(dir.path());
  write_stage_outputs(paths);
  save_run_record(record_with({{"sfm", "done"}, {"mvs", "done"}, {"recon", "done"}, {"texture", "done"}}),
                  paths.run_record);
  const fs::path file = write_run_report(dir.path());
  EXPECT_EQ(file, dir.path() / "report.html");
  const std::string html = hos::testing::read_text(file);
  for (const char* id : {"id=\"outcome\"", "id=\"stages\"", "id=\"photos\"", "id=\"plot-reprojection-error\"",
                         "id=\"plot-track-length\"", "id=\"plot-mvs-confidence\"", "id=\"config\""}) {
    EXPECT_TRUE(contains(html, id)) << id;
  }
  EXPECT_TRUE(contains(html, "The run finished."));
  EXPECT_FALSE(contains(html, "failed-stage"));
  EXPECT_TRUE(contains(html, "src=\"sfm/undistorted/images/view_001.png\""));
  EXPECT_TRUE(contains(html, "view_003.png: not registered"));
  EXPECT_TRUE(contains(html, "notes.txt: skipped (not an image)"));
  EXPECT_TRUE(contains(html, "3 of 9 faces are seen by no photo"));
  EXPECT_TRUE(contains(html, "lambda: 0.2"));
  EXPECT_TRUE(contains(html, "<td>1.5 s</td><td>64 MB</td>"));
  // The track-length plot has one bar of height 3 (all tracks have length 2).
  EXPECT_TRUE(contains(html, "<title>3</title>"));
  EXPECT_FALSE(contains(html, "nan"));
}

TEST(RunReport, FailedRunNamesTheFailingStage) {
  hos::testing::TempDir dir;
  const StagePaths paths(dir.path());
  save_run_record(record_with({{"sfm", "done"}, {"mvs", "done"}, {"recon", "failed"}}), paths.run_record);
  const std::string html = run_report_html(dir.path());
  EXPECT_TRUE(contains(html, "id=\"failed-stage\">recon</b>"));
  EXPECT_TRUE(contains(html, "failed (exit code 5)"));
  EXPECT_TRUE(contains(html, "<td>texture</td><td>not run</td>"));
  EXPECT_TRUE(contains(html, "id=\"stages\""));
  // No stage outputs: no plots, and nothing pretends otherwise.
  EXPECT_FALSE(contains(html, "id=\"plot-"));
}

TEST(RunReport, InterruptedRunIsNamed) {
  hos::testing::TempDir dir;
  save_run_record(record_with({{"sfm", "done"}, {"mvs", "interrupted"}}), StagePaths(dir.path()).run_record);
  const std::string html = run_report_html(dir.path());
  EXPECT_TRUE(contains(html, "id=\"failed-stage\">mvs</b>: it was interrupted"));
}

TEST(RunReport, WorkspaceWithoutRunRecordIsAnInputError) {
  hos::testing::TempDir dir;
  EXPECT_THROW(write_run_report(dir.path()), InputError);
  EXPECT_FALSE(fs::exists(dir.path() / "report.html"));
}

TEST(SvgPlot, HistogramClampsOutliersAndEscapes) {
  const Histogram h = make_histogram({-1.0, 0.1, 0.9, 5.0, std::nan("")}, 2, 0.0, 1.0);
  ASSERT_EQ(h.counts.size(), 2u);
  EXPECT_EQ(h.counts[0], 2);
  EXPECT_EQ(h.counts[1], 2);
  EXPECT_EQ(html_escape("a<b & \"c\">"), "a&lt;b &amp; &quot;c&quot;&gt;");
}

}  // namespace
}  // namespace hos::pipeline
