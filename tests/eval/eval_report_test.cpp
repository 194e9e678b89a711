// eval/eval_report.* and eval/eval_options.*: hos-eval's figures as JSON and
// table rows, where they are written, and its option tables.
#include "eval/eval_report.h"

#include <gtest/gtest.h>

#include <limits>

#include "core/error.h"
#include "eval/eval_options.h"
#include "synth/shapes.h"
#include "tests/support/test_support.h"

namespace hos::eval {
namespace {

TEST(EvalReport, SanityOfAHoledSphereInJsonAndTable) {
  TriangleMesh holed = synth::icosphere(2, 1.0);
  holed.faces.pop_back();  // one triangle missing: three boundary edges
  const EvalReport r = sanity_report(check_mesh_sanity(holed), "m.ply");
  EXPECT_EQ(r.j["boundary_edges"].get<int>(), 3);
  EXPECT_FALSE(r.j["watertight"].get<bool>());
  EXPECT_EQ(r.table.rfind("sanity: m.ply\n", 0), 0u) << r.table;
  EXPECT_NE(r.table.find(table_row("boundary_edges", "3")), std::string::npos) << r.table;
}

TEST(EvalReport, SurfaceScoresOneEntryPerThreshold) {
  SurfaceComparison c;
  c.truth_diagonal = 2.0;
  c.chamfer = 0.25;
  c.scores = {{0.005, 0.01, 0.5, 0.25, 1.0 / 3.0}, {0.01, 0.02, 1.0, 1.0, 1.0}};
  EvalReport r;
  add_surface_comparison(c, r);
  ASSERT_EQ(r.j["thresholds"].size(), 2u);
  EXPECT_DOUBLE_EQ(r.j["f_score"].get<double>(), 1.0) << "the middle entry is the primary score";
  EXPECT_DOUBLE_EQ(r.j["thresholds"][0]["recall"].get<double>(), 0.25);
  EXPECT_NE(r.table.find(table_row("P/R/F @ 0.5% diag", "0.5 / 0.25 / 0.3333")), std::string::npos) << r.table;
  EXPECT_NE(r.table.find(table_row("chamfer", "0.25")), std::string::npos) << r.table;
}

TEST(EvalReport, CurvatureWithoutPointsHasNoDistance) {
  CurvatureStats s;
  s.triangles = 80;
  const EvalReport r = curvature_report(s, "m.ply");
  EXPECT_TRUE(r.j["rms_point_distance"].is_null());
  EXPECT_NE(r.table.find(table_row("RMS points -> surface", "-")), std::string::npos) << r.table;
}

TEST(EvalReport, JsonFileIsWrittenInAFolderNotYetThere) {
  hos::testing::TempDir dir;
  EvalReport r;
  r.j["command"] = "sanity";
  const auto path = dir / "eval" / "s.json";
  write_eval_report(r, true, path.string());
  EXPECT_NE(hos::testing::read_text(path).find("\"command\": \"sanity\""), std::string::npos);
}

TEST(EvalOptions, MeshTableChecksRangesAndThresholds) {
  MeshEvalOptions o;
  OptionSet set("eval");
  register_options(set, o);
  set.apply_assignment("samples", "5000");
  EXPECT_EQ(o.distance.num_samples, 5000u);
  EXPECT_THROW(set.apply_assignment("samples", "10"), ConfigError);
  EXPECT_THROW(set.apply_assignment("min_views", "0"), ConfigError);
  set.apply_assignment("thresholds", "0.01, 0.03");
  resolve_thresholds(o);
  EXPECT_EQ(o.distance.thresholds, (std::vector<double>{0.01, 0.03}));
  o.thresholds = "0.01,x";
  try {
    resolve_thresholds(o);
    FAIL() << "x was taken for a threshold";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "eval.thresholds");
    EXPECT_NE(std::string(e.what()).find("'x'"), std::string::npos) << e.what();
  }
  o.thresholds = "0.01,-0.02";
  EXPECT_THROW(resolve_thresholds(o), ConfigError);
}

}  // namespace
}  // namespace hos::eval
