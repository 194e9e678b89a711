// WS/texture/report.json: what hos-texture writes the pipeline reads back
// field by field, and a missing or damaged file is an InputError naming it.
#include "texture/texture_report.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "core/json_report.h"
#include "tests/support/damaged_file_checks.h"
#include "tests/support/test_support.h"

namespace hos::texture {
namespace {

// Every field away from its default, each value of its own; GPS placement.
TextureReport placed_report() {
  TextureReport r;
  r.input_faces = 300000;
  r.faces = 150000;
  r.views = 12;
  r.visible_face_view_pairs = 900001;
  r.outlier_rejections = 17;
  r.unseen_faces = 118;
  r.charts = 42;
  r.merged_charts = 5;
  r.atlases = {{2048, 1024}, {32, 52}};
  r.texel_scale = 0.75;
  r.atlas_coverage = 0.625;
  r.seam_vertices = 321;
  r.mean_seam_jump_before = 12.5;
  r.mean_seam_jump_after = 3.25;
  r.seam_jumps_before = {0.0, 64.0, {5, 4, 3, 2}};
  r.seam_jumps_after = {0.0, 64.0, {9, 3, 2, 0}};
  r.views_per_face = {0.0, 4.0, {118, 20, 30, 40}};
  r.exposure_gains = {{1.0, 0.95, 1.05}, {0.9, 1.1, 1.0 / 3.0}};
  r.estimated_up = {0.0, 0.0, 1.0};
  for (int i = 0; i < 16; ++i) r.root_matrix[i] = 0.5 * i - 1.0;
  PlacementReport& p = r.placement;
  p.up = {0.0, 0.6, 0.8};
  p.up_method = "GPS";
  p.up_fallback_reason = "camera x axes spread";
  p.x_axis_eigenvalues = {0.01, 0.2, 0.79};
  p.scale = 2.5;
  p.metric = true;
  p.units = "metres from GPS";
  p.units_text = "units: metres from GPS (12 photos, residual 2.1 m)";
  p.gps = GpsFitReport{true, "", 12, 11, 45.5, 2.125, true, 0.125};
  p.geo_origin = GeoPosition{47.25, 8.5, 412.0};
  r.step_seconds = {{"visibility", 2.5}, {"atlas", 0.25}, {"charts", 1.0}};  // not in name order
  return r;
}

void expect_equal(const Histogram& r, const Histogram& w) {
  EXPECT_EQ(r.lo, w.lo);
  EXPECT_EQ(r.hi, w.hi);
  EXPECT_EQ(r.counts, w.counts);
}

void expect_equal(const PlacementReport& r, const PlacementReport& w) {
  EXPECT_EQ(r.up, w.up);
  EXPECT_EQ(r.up_method, w.up_method);
  EXPECT_EQ(r.up_fallback_reason, w.up_fallback_reason);
  EXPECT_EQ(r.x_axis_eigenvalues, w.x_axis_eigenvalues);
  EXPECT_EQ(r.scale, w.scale);
  EXPECT_EQ(r.metric, w.metric);
  EXPECT_EQ(r.units, w.units);
  EXPECT_EQ(r.units_text, w.units_text);
  ASSERT_EQ(r.gps.has_value(), w.gps.has_value());
  if (w.gps) {
    EXPECT_EQ(r.gps->usable, w.gps->usable);
    EXPECT_EQ(r.gps->reason, w.gps->reason);
    EXPECT_EQ(r.gps->photos, w.gps->photos);
    EXPECT_EQ(r.gps->inliers, w.gps->inliers);
    EXPECT_EQ(r.gps->spread_m, w.gps->spread_m);
    EXPECT_EQ(r.gps->rms_residual_m, w.gps->rms_residual_m);
    EXPECT_EQ(r.gps->vertical_from_gps, w.gps->vertical_from_gps);
    EXPECT_EQ(r.gps->tilt_uncertainty_deg, w.gps->tilt_uncertainty_deg);
  }
  ASSERT_EQ(r.geo_origin.has_value(), w.geo_origin.has_value());
  if (w.geo_origin) {
    EXPECT_EQ(r.geo_origin->latitude_deg, w.geo_origin->latitude_deg);
    EXPECT_EQ(r.geo_origin->longitude_deg, w.geo_origin->longitude_deg);
    EXPECT_EQ(r.geo_origin->altitude_m, w.geo_origin->altitude_m);
  }
}

void expect_equal(const TextureReport& r, const TextureReport& w) {
  EXPECT_EQ(r.input_faces, w.input_faces);
  EXPECT_EQ(r.faces, w.faces);
  EXPECT_EQ(r.views, w.views);
  EXPECT_EQ(r.visible_face_view_pairs, w.visible_face_view_pairs);
  EXPECT_EQ(r.outlier_rejections, w.outlier_rejections);
  EXPECT_EQ(r.unseen_faces, w.unseen_faces);
  EXPECT_EQ(r.charts, w.charts);
  EXPECT_EQ(r.merged_charts, w.merged_charts);
  EXPECT_EQ(r.atlases, w.atlases);
  EXPECT_EQ(r.texel_scale, w.texel_scale);
  EXPECT_EQ(r.atlas_coverage, w.atlas_coverage);
  EXPECT_EQ(r.seam_vertices, w.seam_vertices);
  EXPECT_EQ(r.mean_seam_jump_before, w.mean_seam_jump_before);
  EXPECT_EQ(r.mean_seam_jump_after, w.mean_seam_jump_after);
  expect_equal(r.seam_jumps_before, w.seam_jumps_before);
  expect_equal(r.seam_jumps_after, w.seam_jumps_after);
  expect_equal(r.views_per_face, w.views_per_face);
  EXPECT_EQ(r.exposure_gains, w.exposure_gains);
  EXPECT_EQ(r.estimated_up, w.estimated_up);
  EXPECT_EQ(r.root_matrix, w.root_matrix);
  expect_equal(r.placement, w.placement);
  EXPECT_EQ(r.step_seconds, w.step_seconds);
}

TEST(TextureReport, ReadsBackWhatItWrites) {
  hos::testing::TempDir dir;
  const TextureReport written = placed_report();
  write_json_report(dir / "report.json", to_json(written));
  expect_equal(read_texture_report(dir / "report.json"), written);
}

// Without GPS: no fit, no origin on Earth, the camera x axes decided the up.
TEST(TextureReport, PlacementWithoutGpsReadsBackWithoutIt) {
  hos::testing::TempDir dir;
  TextureReport written = placed_report();
  written.placement.gps.reset();
  written.placement.geo_origin.reset();
  written.placement.up_fallback_reason.clear();
  write_json_report(dir / "report.json", to_json(written));
  expect_equal(read_texture_report(dir / "report.json"), written);
  // An origin without altitude keeps none.
  written.placement.geo_origin = GeoPosition{-33.5, 151.25, std::nullopt};
  write_json_report(dir / "report.json", to_json(written));
  expect_equal(read_texture_report(dir / "report.json"), written);
}

TEST(TextureReport, AMissingOrMalformedReportIsAnInputErrorNamingTheFile) {
  hos::testing::expect_input_error_naming_the_file(
      "report.json", [](const std::filesystem::path& file) { read_texture_report(file); },
      {"", "{\"faces\": ", "\"report\"", R"({"unseen_faces": "some"})", R"({"views_per_face": {"lo": 0, "hi": 1}})",
       R"({"exposure_gains": [[1, 2]]})", R"({"placement": {"units_text": 3}})",
       R"({"step_seconds": {"atlas": "slow"}})", R"({"atlases": [[1, "x"]]})"});
}

}  // namespace
}  // namespace hos::texture
