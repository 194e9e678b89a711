// hos-eval's output: each measurement as JSON and as a table of named rows,
// and where they go (--json FILE, a bare --json, or the table alone).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "eval/alignment.h"
#include "eval/curvature.h"
#include "eval/mesh_sanity.h"
#include "eval/surface_distance.h"
#ifdef HOS_EVAL_HAS_RENDER
#include "eval/render_compare.h"
#endif

namespace hos::eval {

// The figures of one measurement: JSON and a human-readable table.
struct EvalReport {
  nlohmann::json j;
  std::string table;
};

// "  name<padding>value\n": one row of the table.
std::string table_row(const std::string& name, const std::string& value);

// The alignment's figures: rows added to report.table, JSON returned.
nlohmann::json alignment_report(const ModelAlignment& alignment, EvalReport& report);

// mesh: accuracy, completeness, Chamfer and the scores at each threshold,
// added to report (which may hold the alignment and visible part already).
void add_surface_comparison(const SurfaceComparison& c, EvalReport& report);
// The part of the truth the cameras see: faces kept of all_faces.
void add_visible_truth(std::size_t visible_faces, std::size_t all_faces, int min_views, EvalReport& report);

EvalReport curvature_report(const CurvatureStats& s, const std::string& mesh_path);
EvalReport sanity_report(const MeshSanity& s, const std::string& mesh_path);
EvalReport cameras_report(const CameraPoseComparison& c, const std::string& model, const std::string& truth);
#ifdef HOS_EVAL_HAS_RENDER
void add_render_comparison(const RenderComparison& c, EvalReport& report);
EvalReport common_report(const CommonComparison& c, const std::vector<std::string>& saved);
#endif

// Writes the report: with json_path the table to stdout and the JSON to the
// file (its folder created); with json_requested and no path the JSON to
// stdout and the table to stderr; otherwise the table to stdout. Throws
// OutputError naming a file that cannot be written.
void write_eval_report(const EvalReport& report, bool json_requested, const std::string& json_path);

}  // namespace hos::eval
