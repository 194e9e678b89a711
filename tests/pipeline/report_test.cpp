#include "pipeline/report/report.h"

#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "core/colmap_io.h"
#include "core/error.h"
#include "mvs/mvs_report.h"
#include "pipeline/report/report_viewer.h"
#include "pipeline/report/svg_plot.h"
#include "pipeline/run_record.h"
#include "pipeline/stage_paths.h"
#include "recon/recon_report.h"
#include "tests/support/test_support.h"
#include "texture/texture_report.h"

namespace hos::pipeline {
namespace {
namespace fs = std::filesystem;
using hos::testing::contains;
using hos::testing::count_occurrences;

// A photo of the given size (a gradient, so that JPEG has something to encode).
void write_photo(const fs::path& file, int width, int height) {
  cv::Mat image(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) image.at<cv::Vec3b>(y, x) = cv::Vec3b(x % 256, y % 256, (x + y) % 256);
  }
  fs::create_directories(file.parent_path());
  ASSERT_TRUE(cv::imwrite(file.string(), image));
}

// The report files of mvs, recon and texture as the stages write them.
void write_stage_reports(const StagePaths& paths) {
  mvs::MvsResult mvs;
  for (int i = 1; i <= 2; ++i) {
    mvs::MvsViewStats view;
    view.name = "view_00" + std::to_string(i) + ".png";
    view.pixels = 100;
    view.valid_pixels = 50 / std::size_t(i);
    mvs.stats.per_view.push_back(view);
  }
  for (int i = 0; i < 100; ++i) {
    mvs.points.positions.emplace_back(float(i), 0.0f, 0.0f);
    mvs.points.confidence.push_back(float(2 + i % 4));
  }
  fs::create_directories(paths.mvs_report.parent_path());
  mvs::write_mvs_report(paths.mvs_report, mvs);

  recon::ReconResult recon;
  recon.stats.residual_history = {1.0, 0.1, 0.01, 0.001};
  fs::create_directories(paths.recon_report.parent_path());
  recon::write_recon_report(paths.recon_report, recon);

  texture::TextureResult texture;
  texture.stats.views_per_face = make_count_histogram({1, 2, 2, 2, 3}, 30);
  texture.stats.seam_jumps_before = make_histogram({40.0, 50.0, 60.0}, 32, 0.0, 128.0);
  texture.stats.seam_jumps_after = make_histogram({1.0, 2.0, 9.0}, 32, 0.0, 128.0);
  fs::create_directories(paths.texture_report.parent_path());
  texture::write_texture_report(paths.texture_report, texture);
}

// Two 1600x1200 photos seeing three points (tracks of 2), one unregistered
// photo, one skipped file, the stages' report files, one hos-eval result.
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
  for (const auto& image : model.images) write_photo(paths.undistorted / "images" / image.second.name, 1600, 1200);
  write_photo(paths.root / "photos" / "view_003.png", 800, 600);
  std::ofstream(paths.sfm_report) << R"({"images_given": 3, "images_registered": 2, "unregistered": ["view_003.png"],
    "registered_fraction": 0.6667, "warning": "only 2 of 3 photos (67%) registered",
    "skipped": [{"file": "notes.txt", "reason": "not an image"}]})";
  write_stage_reports(paths);
  fs::create_directories(paths.eval);
  std::ofstream(paths.eval / "mesh.json")
      << R"({"command": "mesh", "f_score": 0.8125, "accuracy": {"mean": 0.004}, "thresholds": [{"f_score": 0.5}]})";
  fs::create_directories(paths.logs);
  std::ofstream(paths.log("texture"))
      << "[texture] info: start\n[texture] warning: 3 of 9 faces are seen by no photo\n";
  std::ofstream(paths.config) << "recon:\n  lambda: 0.2\n";
}

RunRecord record_with(const std::vector<std::pair<std::string, std::string>>& states,
                      const fs::path& photos = "photos") {
  RunRecord record;
  record.photos = photos.string();
  record.output = "out.glb";
  for (const auto& [stage, state] : states) {
    StageRecord& s = record.stages[stage];
    s.state = state;
    s.wall_seconds = 1.5;
    s.cpu_seconds = 2.75;
    s.peak_memory_bytes = 64 << 20;
    s.exit_code = state == "failed" ? 5 : 0;
  }
  return record;
}

TEST(RunReport, FinishedRunHasEveryTableAndPlot) {
  hos::testing::TempDir dir;
  const StagePaths paths(dir.path());
  write_stage_outputs(paths);
  save_run_record(
      record_with({{"sfm", "done"}, {"mvs", "done"}, {"recon", "done"}, {"texture", "done"}}, paths.root / "photos"),
      paths.run_record);
  const fs::path file = write_run_report(dir.path());
  EXPECT_EQ(file, dir.path() / "report.html");
  const std::string html = hos::testing::read_text(file);
  for (const char* id : {"id=\"outcome\"", "id=\"stages\"", "id=\"photos\"", "id=\"plot-reprojection-error\"",
                         "id=\"plot-track-length\"", "id=\"plot-depth-coverage\"", "id=\"plot-mvs-confidence\"",
                         "id=\"plot-solver-residual\"", "id=\"plot-views-per-face\"", "id=\"plot-seam-jump\"",
                         "id=\"eval\"", "id=\"config\""}) {
    EXPECT_EQ(count_occurrences(html, id), 1) << id;
  }
  EXPECT_TRUE(contains(html, "The run finished."));
  // Paths as seen from the page: the same wherever the workspace is.
  EXPECT_TRUE(contains(html, "photos: <code>photos</code>"));
  EXPECT_FALSE(contains(html, "failed-stage"));
  EXPECT_TRUE(contains(html, "view_001.png: registered"));
  EXPECT_TRUE(contains(html, "view_003.png: not registered"));
  EXPECT_TRUE(contains(html, "2 of 3 photos registered (67%): <strong>only 2 of 3 photos (67%) registered"));
  EXPECT_TRUE(contains(html, "notes.txt: skipped (not an image)"));
  EXPECT_TRUE(contains(html, "3 of 9 faces are seen by no photo"));
  EXPECT_TRUE(contains(html, "lambda: 0.2"));
  EXPECT_TRUE(contains(html, "<th>time</th><th>CPU time</th>"));
  EXPECT_TRUE(contains(html, "<td>1.5 s</td><td>2.8 s</td><td>64 MB</td>"));
  // The track-length plot has one bar of height 3 (all tracks have length 2).
  EXPECT_TRUE(contains(html, "<title>3</title>"));
  // Each plot shows its data: coverage per view, the residual's decades,
  // both seam histograms, the faces seen by two photos.
  EXPECT_TRUE(contains(html, "<title>view_001.png: 0.5</title>"));
  EXPECT_TRUE(contains(html, "<title>view_002.png: 0.25</title>"));
  EXPECT_TRUE(contains(html, ">1e0</text>"));
  EXPECT_TRUE(contains(html, ">1e-3</text>"));
  EXPECT_TRUE(contains(html, ">before leveling</text>"));
  EXPECT_TRUE(contains(html, ">after leveling</text>"));
  EXPECT_EQ(count_occurrences(html, "<polyline"), 1);
  // hos-eval's numbers, nested ones by their path; lists stay in the file.
  EXPECT_TRUE(contains(html, "<h3>eval/mesh.json</h3>"));
  EXPECT_EQ(count_occurrences(html, "<td>f_score</td><td>0.8125</td>"), 2);  // a headline, and in all figures
  EXPECT_EQ(count_occurrences(html, "<td>accuracy.mean</td><td>0.004</td>"), 2);
  EXPECT_LT(html.find("<td>f_score</td>"), html.find("<td>accuracy.mean</td>"));
  EXPECT_FALSE(contains(html, "<td>thresholds"));
  EXPECT_FALSE(contains(html, "nan"));
}

TEST(RunReport, PhotosAreSmallEmbeddedThumbnails) {
  hos::testing::TempDir dir;
  const StagePaths paths(dir.path());
  write_stage_outputs(paths);
  save_run_record(record_with({{"sfm", "done"}}, paths.root / "photos"), paths.run_record);
  // The thumbnail hos-sfm wrote is embedded as it is; the others are made
  // from the photos.
  const cv::Mat small(12, 16, CV_8UC3, cv::Scalar(10, 200, 30));
  std::vector<unsigned char> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", small, jpeg));
  fs::create_directories(paths.thumbnails);
  std::ofstream(paths.thumbnails / "view_002.png.jpg", std::ios::binary)
      .write(reinterpret_cast<const char*>(jpeg.data()), std::streamsize(jpeg.size()));
  const std::string html = run_report_html(dir.path());
  EXPECT_TRUE(contains(html, "src=\"data:image/jpeg;base64," + base64(std::string(jpeg.begin(), jpeg.end())) + "\""));
  // Two registered photos and the unregistered one, all embedded; the
  // skipped text file has no picture.
  const std::string prefix = "src=\"data:image/jpeg;base64,";
  ASSERT_EQ(count_occurrences(html, prefix), 3);
  EXPECT_FALSE(contains(html, "src=\"sfm/"));
  for (auto at = html.find(prefix); at != std::string::npos; at = html.find(prefix, at + 1)) {
    const auto length = html.find('"', at + prefix.size()) - (at + prefix.size());
    // A 160 px wide JPEG: a few KB, where the 1600x1200 photo is megabytes.
    EXPECT_LT(length, 20000u);
    EXPECT_GT(length, 200u);
  }
}

// Photos in subfolders: each registered photo once, under its name (its
// path in the photo folder), with the thumbnail hos-sfm wrote for that name.
TEST(RunReport, PhotosInSubfoldersAreShownUnderTheirNames) {
  hos::testing::TempDir dir;
  const StagePaths paths(dir.path());
  write_stage_outputs(paths);
  save_run_record(record_with({{"sfm", "done"}}, paths.root / "photos"), paths.run_record);
  fs::create_directories(paths.undistorted / "images" / "DCIM" / "100APPLE");
  write_photo(paths.undistorted / "images" / "DCIM" / "100APPLE" / "IMG_1.jpg", 64, 48);
  const cv::Mat small(12, 16, CV_8UC3, cv::Scalar(200, 20, 30));
  std::vector<unsigned char> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", small, jpeg));
  fs::create_directories(paths.thumbnails / "DCIM" / "100APPLE");
  std::ofstream(paths.thumbnails / "DCIM" / "100APPLE" / "IMG_1.jpg.jpg", std::ios::binary)
      .write(reinterpret_cast<const char*>(jpeg.data()), std::streamsize(jpeg.size()));
  const std::string html = run_report_html(dir.path());
  EXPECT_TRUE(contains(html, "<figcaption>DCIM/100APPLE/IMG_1.jpg: registered</figcaption>"));
  EXPECT_TRUE(contains(html, "src=\"data:image/jpeg;base64," + base64(std::string(jpeg.begin(), jpeg.end())) + "\""));
  EXPECT_FALSE(contains(html, "<figcaption>DCIM: "));
  EXPECT_EQ(count_occurrences(html, "src=\"data:image/jpeg;base64,"), 4);
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
  EXPECT_FALSE(contains(html, "id=\"eval\""));
}

TEST(RunReport, FailedRunShowsThePlotsOfTheStagesBeforeIt) {
  hos::testing::TempDir dir;
  const StagePaths paths(dir.path());
  write_stage_outputs(paths);
  fs::remove(paths.recon_report);
  fs::remove(paths.texture_report);
  save_run_record(record_with({{"sfm", "done"}, {"mvs", "done"}, {"recon", "failed"}}), paths.run_record);
  const std::string html = run_report_html(dir.path());
  EXPECT_TRUE(contains(html, "id=\"failed-stage\">recon</b>"));
  EXPECT_TRUE(contains(html, "id=\"plot-depth-coverage\""));
  EXPECT_FALSE(contains(html, "id=\"plot-solver-residual\""));
  EXPECT_FALSE(contains(html, "id=\"plot-seam-jump\""));
}

TEST(RunReport, DamagedReportFileLeavesOutItsPlotsOnly) {
  hos::testing::TempDir dir;
  const StagePaths paths(dir.path());
  write_stage_outputs(paths);
  std::ofstream(paths.mvs_report) << R"({"per_view": 3, "confidence": {"lo": "x"}})";
  save_run_record(record_with({{"sfm", "done"}, {"mvs", "done"}}), paths.run_record);
  const std::string html = run_report_html(dir.path());
  EXPECT_FALSE(contains(html, "id=\"plot-depth-coverage\""));
  EXPECT_TRUE(contains(html, "id=\"plot-solver-residual\""));
}

TEST(RunReport, InterruptedRunIsNamed) {
  hos::testing::TempDir dir;
  save_run_record(record_with({{"sfm", "done"}, {"mvs", "interrupted"}}), StagePaths(dir.path()).run_record);
  const std::string html = run_report_html(dir.path());
  EXPECT_TRUE(contains(html, "id=\"failed-stage\">mvs</b>: it was interrupted"));
}

TEST(RunReport, FolderThatIsNoWorkspaceIsAnInputError) {
  hos::testing::TempDir dir;
  EXPECT_THROW(write_run_report(dir.path()), InputError);
  EXPECT_FALSE(fs::exists(dir.path() / "report.html"));
}

// hos-pipeline writes config.yaml before the first stage: a run that stopped
// before it (a Slurm that cannot be reached, a full disk) has only that.
TEST(RunReport, WorkspaceWhereNothingRanYetSaysSo) {
  hos::testing::TempDir dir;
  const StagePaths paths(dir.path());
  std::ofstream(paths.config) << "recon:\n  lambda: 0.2\n";
  const std::string html = run_report_html(dir.path());
  EXPECT_TRUE(contains(html, "No stage has run in this workspace yet")) << html;
  EXPECT_FALSE(contains(html, "The run finished"));
  EXPECT_TRUE(contains(html, "<td>sfm</td><td>not run</td>"));
  EXPECT_TRUE(fs::exists(write_run_report(dir.path())));
}

TEST(SvgPlot, EscapesText) { EXPECT_EQ(html_escape("a<b & \"c\">"), "a&lt;b &amp; &quot;c&quot;&gt;"); }

TEST(SvgPlot, GroupedHistogramsDrawEveryBinOfEverySeriesWithALegend) {
  const Histogram a = make_histogram({0.1, 0.6, 0.7}, 2, 0.0, 1.0);
  const Histogram b = make_histogram({0.1}, 2, 0.0, 1.0);
  const std::string svg = svg_histograms({{"first", a}, {"second", b}}, {"title", "x", ""});
  EXPECT_EQ(count_occurrences(svg, "<rect x="), 4 + 2);  // bars and legend swatches
  EXPECT_TRUE(contains(svg, "<title>2</title>"));
  EXPECT_TRUE(contains(svg, ">second</text>"));
  EXPECT_FALSE(contains(svg_histogram(a, {"title", "x", ""}), ">first</text>"));
}

TEST(SvgPlot, CountHistogramsAreLabelledByTheirFirstAndLastCount) {
  const std::string svg = svg_histogram(make_count_histogram({0, 1, 3}, 10), {"views", "photos", ""});
  EXPECT_TRUE(contains(svg, ">0</text>"));
  EXPECT_TRUE(contains(svg, ">3</text>"));
  EXPECT_FALSE(contains(svg, ">-0.5</text>"));
}

TEST(SvgPlot, LogLinePlotLeavesOutValuesItCannotPlace) {
  const std::string svg = svg_log_line_plot({1.0, 0.0, 0.05, std::nan(""), 0.002}, {"residual", "iteration", ""});
  const auto points = svg.substr(svg.find("points=\""));
  EXPECT_EQ(count_occurrences(points.substr(0, points.find("/>")), ","), 3);
  EXPECT_TRUE(contains(svg, ">1e0</text>"));
  EXPECT_TRUE(contains(svg, ">1e-3</text>"));
}

}  // namespace
}  // namespace hos::pipeline
