// The run report's plots read on their own (axis labels, ticks, a marker per
// solve, where the time went), its page stays small whatever the model, and
// its viewer's scripts come in the order the model needs.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <regex>

#include "core/glb_container.h"
#include "core/histogram.h"
#include "pipeline/report/report.h"
#include "pipeline/report/report_plots.h"
#include "pipeline/report/report_viewer.h"
#include "pipeline/report/svg_plot.h"
#include "pipeline/run_record.h"
#include "pipeline/stage_paths.h"
#include "tests/support/test_support.h"
#include "texture/gltf_writer.h"

namespace hos::pipeline {
namespace {
namespace fs = std::filesystem;
using hos::testing::contains;
using hos::testing::count_occurrences;

constexpr std::size_t kMaxPageBytes = 8'000'000;

// The x1 attributes of the lines of a class, in order.
std::vector<double> line_xs(const std::string& svg, const std::string& css_class) {
  std::vector<double> xs;
  const std::regex line("<line class=\"" + css_class + "\" x1=\"([-0-9.e]+)\"");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), line); it != std::sregex_iterator(); ++it) {
    xs.push_back(std::stod((*it)[1]));
  }
  return xs;
}

TEST(PlotAxes, TicksAreRoundStepsInsideTheRange) {
  for (const auto& [lo, hi] : std::vector<std::pair<double, double>>{
           {0.0, 1.0}, {0.0, 1.01}, {-0.5, 3.5}, {2.0, 31.0}, {0.0, 173.0}, {1e-4, 3e-3}, {0.0, 1e6}, {7.0, 7.3}}) {
    const std::vector<double> ticks = axis_ticks(lo, hi);
    ASSERT_GE(ticks.size(), 2u) << lo << " " << hi;
    EXPECT_LE(ticks.size(), 7u) << lo << " " << hi;
    EXPECT_GE(ticks.front(), lo - 1e-12);
    EXPECT_LE(ticks.back(), hi + 1e-12);
    const double step = ticks[1] - ticks[0];
    const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
    EXPECT_TRUE(std::abs(mantissa - 1) < 1e-6 || std::abs(mantissa - 2) < 1e-6 || std::abs(mantissa - 5) < 1e-6)
        << step;
  }
  // Counts never get fractional ticks.
  for (double t : axis_ticks(-0.5, 2.5, 5, 1.0)) EXPECT_EQ(t, std::round(t));
  EXPECT_TRUE(axis_ticks(1.0, 1.0).empty());
}

TEST(PlotAxes, HistogramHasBothAxisLabelsAFewTicksAndGridlines) {
  std::vector<double> values(200);
  for (int i = 0; i < 200; ++i) values[i] = 0.01 * i;
  const std::string svg =
      svg_histogram(make_histogram(values, 30, 0.0, 2.0), {"sfm: error", "mean reprojection error (px)", ""});
  EXPECT_TRUE(contains(svg, "class=\"x-label\""));
  EXPECT_TRUE(contains(svg, ">mean reprojection error (px)</text>"));
  EXPECT_TRUE(contains(svg, ">count</text>"));  // the histogram's default y label
  EXPECT_GE(count_occurrences(svg, "class=\"x-tick\""), 3);
  EXPECT_LE(count_occurrences(svg, "class=\"x-tick\""), 7);
  EXPECT_GE(count_occurrences(svg, "class=\"y-tick\""), 3);
  EXPECT_LE(count_occurrences(svg, "class=\"y-tick\""), 7);
  EXPECT_EQ(count_occurrences(svg, "class=\"grid\""),
            count_occurrences(svg, "class=\"x-tick\"") + count_occurrences(svg, "class=\"y-tick\""));
  // It scales with its container: a viewBox and no fixed size.
  EXPECT_TRUE(contains(svg, "viewBox=\"0 0 "));
  EXPECT_FALSE(contains(svg, " width=\"480\""));
}

TEST(PlotAxes, BarChartAndLogPlotCarryTheirYLabel) {
  const std::string bars = svg_bar_chart({{"a", 0.5}, {"b", 0.9}, {"c", 0.1}}, 1.0, {"cov", "view", "fraction"});
  EXPECT_TRUE(contains(bars, ">fraction</text>"));
  EXPECT_GE(count_occurrences(bars, "class=\"y-tick\""), 3);
  EXPECT_EQ(count_occurrences(bars, "class=\"x-tick\""), 3);  // views 1, 2, 3
  const std::string line = svg_log_line_plot({1.0, 0.1, 0.01, 0.001}, {"r", "iteration", "relative residual"});
  EXPECT_TRUE(contains(line, ">relative residual</text>"));
  EXPECT_EQ(count_occurrences(line, "class=\"y-tick\""), 4);  // 1e0 .. 1e-3
}

TEST(SolverResidualPlot, MarksWhereEachSolveStarts) {
  const std::vector<int> solves = {4, 3, 5};
  std::vector<double> residuals;
  for (int n : solves) {
    for (int i = 0; i < n; ++i) residuals.push_back(std::pow(0.1, i + 1));
  }
  const std::string svg = svg_log_line_plot(residuals, {"r", "iteration", "relative residual"}, solves);
  const std::vector<double> xs = line_xs(svg, "segment-marker");
  ASSERT_EQ(xs.size(), solves.size());
  // Between the last iteration of one solve and the first of the next: the
  // polyline's x of iterations 4 and 5 (solve 2 starts at index 4).
  const std::regex point("([-0-9.e]+),[-0-9.e]+ ");
  const std::string points = svg.substr(svg.find("points=\"") + 8);
  std::vector<double> px;
  for (auto it = std::sregex_iterator(points.begin(), points.end(), point); it != std::sregex_iterator(); ++it) {
    px.push_back(std::stod((*it)[1]));
  }
  ASSERT_EQ(px.size(), residuals.size());
  EXPECT_LE(xs[0], px[0]);
  EXPECT_GT(xs[1], px[3]);
  EXPECT_LT(xs[1], px[4]);
  EXPECT_GT(xs[2], px[6]);
  EXPECT_LT(xs[2], px[7]);
}

TEST(SolverResidualPlot, TheReportDrawsOneMarkerPerSolveOfReconsReport) {
  hos::testing::TempDir dir("hos-report-layout");
  const StagePaths paths(dir.path());
  fs::create_directories(paths.recon_report.parent_path());
  std::ofstream(paths.recon_report) << R"({"residual_history": [0.5, 0.05, 0.005, 0.4, 0.004],
                                           "solve_iterations": [3, 2]})";
  std::ofstream(paths.config) << "recon: {}\n";
  const std::string html = run_report_html(dir.path());
  const auto start = html.find("<div id=\"plot-solver-residual\">");
  ASSERT_NE(start, std::string::npos);
  const std::string plot = html.substr(start, html.find("</div>", start) - start);
  EXPECT_EQ(count_occurrences(plot, "class=\"segment-marker\""), 2);
  EXPECT_TRUE(contains(plot, "relative residual"));
}

TEST(StageTimePlot, OneWallAndOneCpuBarPerStageThatEnded) {
  RunRecord record;
  record.stages["sfm"].state = "done";
  record.stages["sfm"].wall_seconds = 12.0;
  record.stages["sfm"].cpu_seconds = 20.0;
  record.stages["mvs"].state = "failed";
  record.stages["mvs"].wall_seconds = 60.0;
  record.stages["mvs"].cpu_seconds = 110.0;
  record.stages["recon"].state = "running";
  const std::string svg = stage_time_svg(record);
  EXPECT_EQ(count_occurrences(svg, "<title>sfm, "), 2);
  EXPECT_EQ(count_occurrences(svg, "<title>mvs, "), 2);
  EXPECT_EQ(count_occurrences(svg, "<title>recon, "), 0);
  EXPECT_TRUE(contains(svg, "<title>mvs, CPU time: 110</title>"));
  EXPECT_TRUE(contains(svg, ">time (s)</text>"));
  EXPECT_GE(count_occurrences(svg, "class=\"x-tick\""), 3);
  EXPECT_EQ(stage_time_svg(RunRecord{}), "");
}

// A binary glTF with no mesh: the JSON chunk, then a binary chunk of
// `payload` bytes (the size of a model's geometry and atlas).
void write_glb(const fs::path& file, const std::string& generator, std::size_t payload) {
  std::string json = R"({"asset":{"version":"2.0","generator":")" + generator + R"("},"scene":0,"scenes":[{}]})";
  json.resize((json.size() + 3) / 4 * 4, ' ');
  payload = (payload + 3) / 4 * 4;
  const auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  std::ofstream out(file, std::ios::binary);
  out << "glTF" << u32(2) << u32(std::uint32_t(12 + 8 + json.size() + 8 + payload)) << u32(std::uint32_t(json.size()))
      << "JSON" << json << u32(std::uint32_t(payload)) << std::string("BIN\0", 4) << std::string(payload, '\x5a');
}

// A workspace whose texture stage wrote a model of model_bytes, and a
// stand-in for model-viewer's script of its real size (about 1 MB).
struct ModelWorkspace {
  explicit ModelWorkspace(std::size_t model_bytes) : paths(dir.path()) {
    fs::create_directories(paths.textured_model.parent_path());
    std::ofstream(paths.config) << "texture: {}\n";
    write_glb(paths.textured_model, "full", model_bytes);
    std::ofstream(script) << "/*" << std::string(1'100'000, 'x') << "*/";
  }
  hos::testing::TempDir dir{"hos-report-layout"};
  StagePaths paths;
  fs::path script = dir.path() / "viewer.js";
};

TEST(ReportPageSize, BigModelWithoutPreviewIsLinkedAndThePageStaysSmall) {
  ModelWorkspace ws(30'000'000);
  const std::string html = run_report_html(ws.dir.path(), {ws.script});
  EXPECT_LT(html.size(), kMaxPageBytes);
  EXPECT_TRUE(contains(html, "href=\"texture/model.glb\""));
  EXPECT_FALSE(contains(html, "data:model/gltf-binary"));
}

TEST(ReportPageSize, PreviewIsShownAndTheFullModelLinked) {
  ModelWorkspace ws(30'000'000);
  write_glb(report_preview_model(ws.paths), "preview", 3'000'000);
  EXPECT_EQ(report_preview_model(ws.paths).filename(), "model.preview.glb");
  const std::string html = run_report_html(ws.dir.path(), {ws.script});
  EXPECT_LT(html.size(), kMaxPageBytes);
  EXPECT_TRUE(contains(html, "data:model/gltf-binary;base64," + base64(read_bytes(report_preview_model(ws.paths)))));
  EXPECT_TRUE(contains(html, "href=\"texture/model.glb\""));
}

TEST(ReportPageSize, PreviewTooLargeForThePageIsLinkedNotEmbedded) {
  ModelWorkspace ws(30'000'000);
  write_glb(report_preview_model(ws.paths), "preview", 9'000'000);
  const std::string html = run_report_html(ws.dir.path(), {ws.script});
  EXPECT_LT(html.size(), kMaxPageBytes);
  EXPECT_FALSE(contains(html, "data:model/gltf-binary"));
  EXPECT_TRUE(contains(html, "href=\"texture/model.glb\""));
  EXPECT_TRUE(contains(html, "texture/model.preview.glb, 9 MB"));
}

TEST(ReportPageSize, SmallModelWithoutPreviewIsShownItself) {
  ModelWorkspace ws(200'000);
  const std::string html = run_report_html(ws.dir.path(), {ws.script});
  EXPECT_TRUE(contains(html, "data:model/gltf-binary;base64," + base64(read_bytes(ws.paths.textured_model))));
  EXPECT_TRUE(contains(html, "href=\"texture/model.glb\""));
}

// A one-triangle model as hos-texture writes it, its geometry compressed as
// mesh_compression says.
void write_triangle_model(const fs::path& file, const std::string& mesh_compression) {
  texture::TexturedMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.normals.assign(3, Eigen::Vector3f(0, 0, 1));
  mesh.uvs = {{0, 1}, {1, 1}, {0, 0}};
  mesh.indices = {{0, 1, 2}};
  mesh.atlases = {cv::Mat(4, 4, CV_8UC3, cv::Scalar(40, 80, 120))};
  texture::GltfWriteOptions options;
  options.mesh_compression = mesh_compression;
  texture::write_glb(file, mesh, options);
}

// Where the viewer's bundle (the workspace's stand-in) and the meshopt
// decoder location are in the page, relative to the <model-viewer> element.
struct ViewerOrder {
  bool decoder_location = false;
  bool bundle_first = false;
};
ViewerOrder viewer_order(const std::string& html) {
  const auto element = html.find("<model-viewer id=\"viewer\"");
  const auto bundle = html.find("/*xxx");
  const auto decoder = html.find("meshoptDecoderLocation");
  EXPECT_NE(element, std::string::npos);
  EXPECT_NE(bundle, std::string::npos);
  EXPECT_TRUE(decoder == std::string::npos || decoder < element) << "the decoder location after the element";
  return {decoder != std::string::npos, bundle < element};
}

// A meshopt-compressed preview needs the bundle and its decoder location
// before the element; a model that only mentions the extension (in a name,
// in extras) is not compressed and keeps the bundle after it.
TEST(ReportViewer, OnlyAModelThatRequiresMeshoptGetsTheDecoderFirst) {
  ModelWorkspace ws(1000);
  const fs::path preview = report_preview_model(ws.paths);
  write_triangle_model(preview, "meshopt");
  ViewerOrder order = viewer_order(run_report_html(ws.dir.path(), {ws.script}));
  EXPECT_TRUE(order.decoder_location);
  EXPECT_TRUE(order.bundle_first);

  write_triangle_model(preview, "quantized");
  const GlbChunks chunks = split_glb(read_bytes(preview), preview.string());
  nlohmann::json json = nlohmann::json::parse(chunks.json);
  ASSERT_EQ(json["extensionsRequired"], nlohmann::json::array({"KHR_mesh_quantization"}));
  json["asset"]["extras"]["note"] = "not EXT_meshopt_compression";
  json["meshes"][0]["name"] = "EXT_meshopt_compression";
  std::ofstream(preview, std::ios::binary) << join_glb(json.dump(), chunks.bin);
  order = viewer_order(run_report_html(ws.dir.path(), {ws.script}));
  EXPECT_FALSE(order.decoder_location);
  EXPECT_FALSE(order.bundle_first);
}

TEST(ReportLayout, PageFitsTheWindowsWidth) {
  ModelWorkspace ws(1000);
  const std::string html = run_report_html(ws.dir.path(), {ws.script});
  EXPECT_TRUE(contains(html, "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"));
  EXPECT_TRUE(contains(html, "max-width: none"));
  EXPECT_TRUE(contains(html, "svg.plot { display: block; width: 100%; height: auto; }"));
}

}  // namespace
}  // namespace hos::pipeline
