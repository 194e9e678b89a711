#include "eval/eval_report.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json_report.h"

namespace hos::eval {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// JSON has no infinity: +inf (identical images) is written as null.
[[maybe_unused]] json number(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

std::string fmt(double x, int precision = 6) {
  std::ostringstream s;
  s << std::setprecision(precision) << x;
  return s.str();
}

json to_json(const Similarity3& s) {
  json j;
  j["scale"] = s.scale;
  j["rotation"] = {
      {s.R(0, 0), s.R(0, 1), s.R(0, 2)}, {s.R(1, 0), s.R(1, 1), s.R(1, 2)}, {s.R(2, 0), s.R(2, 1), s.R(2, 2)}};
  j["translation"] = {s.t.x(), s.t.y(), s.t.z()};
  return j;
}

json to_json(const DistanceStats& d) {
  return {{"mean", d.mean}, {"median", d.median}, {"p90", d.p90}, {"rms", d.rms}, {"max", d.max}, {"count", d.count}};
}

}  // namespace

std::string table_row(const std::string& name, const std::string& value) {
  std::ostringstream s;
  s << "  " << std::left << std::setw(34) << name << value << "\n";
  return s.str();
}

json alignment_report(const ModelAlignment& a, EvalReport& report) {
  report.table += table_row("aligned cameras", std::to_string(a.names.size()));
  report.table += table_row("alignment scale", fmt(a.truth_from_recovered.scale));
  report.table += table_row("alignment RMS residual", fmt(a.rms_residual));
  json j = to_json(a.truth_from_recovered);
  j["cameras"] = a.names.size();
  j["rms_residual"] = a.rms_residual;
  return j;
}

void add_visible_truth(std::size_t visible_faces, std::size_t all_faces, int min_views, EvalReport& r) {
  r.j["truth_faces_visible"] = visible_faces;
  r.table += table_row("true faces seen by >= " + std::to_string(min_views) + " views",
                       std::to_string(visible_faces) + " of " + std::to_string(all_faces));
}

void add_surface_comparison(const SurfaceComparison& c, EvalReport& r) {
  r.j["truth_diagonal"] = c.truth_diagonal;
  r.j["result_is_points"] = c.result_is_points;
  r.j["accuracy"] = to_json(c.accuracy);
  r.j["completeness"] = to_json(c.completeness);
  r.j["chamfer"] = c.chamfer;
  r.j["f_score"] = c.primary().f_score;
  r.j["f_score_threshold"] = c.primary().fraction;
  r.j["thresholds"] = json::array();
  r.table += table_row("truth bbox diagonal", fmt(c.truth_diagonal));
  r.table += table_row("accuracy mean/median/p90",
                       fmt(c.accuracy.mean) + " / " + fmt(c.accuracy.median) + " / " + fmt(c.accuracy.p90));
  r.table += table_row("completeness mean/median/p90",
                       fmt(c.completeness.mean) + " / " + fmt(c.completeness.median) + " / " + fmt(c.completeness.p90));
  r.table += table_row("chamfer", fmt(c.chamfer));
  for (const auto& s : c.scores) {
    r.j["thresholds"].push_back({{"fraction", s.fraction},
                                 {"distance", s.distance},
                                 {"precision", s.precision},
                                 {"recall", s.recall},
                                 {"f_score", s.f_score}});
    r.table += table_row("P/R/F @ " + fmt(100.0 * s.fraction, 3) + "% diag",
                         fmt(s.precision, 4) + " / " + fmt(s.recall, 4) + " / " + fmt(s.f_score, 4));
  }
}

EvalReport curvature_report(const CurvatureStats& s, const std::string& mesh_path) {
  EvalReport r;
  r.j = {{"triangles", s.triangles},
         {"vertices_measured", s.vertices_measured},
         {"mean_abs_mean_curvature", s.mean_abs_h},
         {"max_abs_mean_curvature", s.max_abs_h},
         {"mean_abs_gaussian_curvature", s.mean_abs_k},
         {"max_abs_gaussian_curvature", s.max_abs_k},
         {"p99_abs_mean_curvature", s.p99_abs_h},
         {"p99_abs_gaussian_curvature", s.p99_abs_k},
         {"rms_point_distance", s.rms_point_distance ? json(*s.rms_point_distance) : json(nullptr)}};
  r.table += "curvature: " + mesh_path + " (cotangent Laplacian H, angle-defect K, mixed Voronoi areas)\n";
  r.table += table_row("triangles", std::to_string(s.triangles));
  r.table += table_row("RMS points -> surface", s.rms_point_distance ? fmt(*s.rms_point_distance) : "-");
  r.table += table_row("avg / max |H|", fmt(s.mean_abs_h) + " / " + fmt(s.max_abs_h));
  r.table += table_row("avg / max |K|", fmt(s.mean_abs_k) + " / " + fmt(s.max_abs_k));
  r.table += table_row("p99 |H| / |K|", fmt(s.p99_abs_h) + " / " + fmt(s.p99_abs_k));
  return r;
}

EvalReport sanity_report(const MeshSanity& s, const std::string& mesh_path) {
  EvalReport r;
  r.j = {{"vertices", s.vertices},
         {"unreferenced_vertices", s.unreferenced_vertices},
         {"faces", s.faces},
         {"edges", s.edges},
         {"boundary_edges", s.boundary_edges},
         {"non_manifold_edges", s.non_manifold_edges},
         {"non_manifold_vertices", s.non_manifold_vertices},
         {"inconsistent_edges", s.inconsistent_edges},
         {"degenerate_faces", s.degenerate_faces},
         {"components", s.components},
         {"euler_characteristic", s.euler_characteristic},
         {"edge_manifold", s.edge_manifold},
         {"vertex_manifold", s.vertex_manifold},
         {"watertight", s.watertight},
         {"consistently_oriented", s.consistently_oriented},
         {"genus", s.genus ? json(*s.genus) : json(nullptr)}};
  r.table += "sanity: " + mesh_path + "\n";
  for (const auto& [key, value] : r.j.items()) r.table += table_row(key, value.dump());
  return r;
}

EvalReport cameras_report(const CameraPoseComparison& c, const std::string& model, const std::string& truth) {
  EvalReport r;
  r.j["alignment"] = to_json(c.truth_from_recovered);
  r.j["scene_size"] = c.scene_size;
  r.j["images_recovered"] = c.num_recovered;
  r.j["images_truth"] = c.num_truth;
  r.j["images_matched"] = c.cameras.size();
  r.j["center_error"] = {{"mean", c.mean_center_error}, {"median", c.median_center_error}, {"max", c.max_center_error}};
  r.j["rotation_error_deg"] = {
      {"mean", c.mean_rotation_error_deg}, {"median", c.median_rotation_error_deg}, {"max", c.max_rotation_error_deg}};
  r.j["cameras"] = json::array();
  for (const auto& e : c.cameras) {
    r.j["cameras"].push_back(
        {{"name", e.name}, {"center_error", e.center_error}, {"rotation_error_deg", e.rotation_error_deg}});
  }
  r.table += "cameras: " + model + " vs " + truth + "\n";
  r.table += table_row(
      "matched / recovered / truth",
      std::to_string(c.cameras.size()) + " / " + std::to_string(c.num_recovered) + " / " + std::to_string(c.num_truth));
  r.table += table_row("alignment scale", fmt(c.truth_from_recovered.scale));
  r.table += table_row("centre error mean/median/max", fmt(c.mean_center_error) + " / " + fmt(c.median_center_error) +
                                                           " / " + fmt(c.max_center_error) + " (x scene size " +
                                                           fmt(c.scene_size) + ")");
  r.table += table_row("rotation error mean/median/max", fmt(c.mean_rotation_error_deg) + " / " +
                                                             fmt(c.median_rotation_error_deg) + " / " +
                                                             fmt(c.max_rotation_error_deg) + " deg");
  return r;
}

#ifdef HOS_EVAL_HAS_RENDER

void add_render_comparison(const RenderComparison& c, EvalReport& r) {
  r.j["mean_psnr"] = number(c.mean_psnr);
  r.j["mean_ssim"] = c.mean_ssim;
  r.j["skipped_views"] = c.skipped_views;
  r.j["views"] = json::array();
  for (const auto& v : c.views) {
    r.j["views"].push_back(
        {{"name", v.name}, {"mask_pixels", v.mask_pixels}, {"psnr", number(v.psnr)}, {"ssim", v.ssim}});
    r.table += table_row(v.name, "PSNR " + fmt(v.psnr, 4) + " dB  SSIM " + fmt(v.ssim, 4));
  }
  r.table += table_row("mean", "PSNR " + fmt(c.mean_psnr, 4) + " dB  SSIM " + fmt(c.mean_ssim, 4));
}

namespace {

// Tiles or regions as JSON (key) and table rows (name X,Y[,WxH]).
void add_regions(EvalReport& r,
                 const std::string& key,
                 const std::string& name,
                 const std::vector<ErrorRegion>& regions) {
  r.j[key] = json::array();
  for (const ErrorRegion& e : regions) {
    r.j[key].push_back({{"x", e.rect.x},
                        {"y", e.rect.y},
                        {"width", e.rect.width},
                        {"height", e.rect.height},
                        {"common_pixels", e.common_pixels},
                        {"share", e.share},
                        {"mse", e.mse}});
    std::ostringstream label, value;
    label << name << " " << e.rect.x << "," << e.rect.y;
    if (name != "tile") label << " " << e.rect.width << "x" << e.rect.height;
    if (e.common_pixels == 0) {
      value << "no pixel all runs cover";
    } else {
      value << "share " << fmt(e.share, 3) << "  MSE per run";
      for (double m : e.mse) value << " " << fmt(m, 4);
    }
    r.table += table_row(label.str(), value.str());
  }
}

}  // namespace

EvalReport common_report(const CommonComparison& c, const std::vector<std::string>& saved) {
  EvalReport r;
  const auto share = [&](std::size_t pixels) { return static_cast<double>(pixels) / c.photo_pixels; };
  r.j["photo_pixels"] = c.photo_pixels;
  r.j["common_coverage"] = share(c.common_pixels);
  r.j["runs"] = json::array();
  r.table += table_row("common coverage", fmt(share(c.common_pixels), 4));
  for (std::size_t i = 0; i < saved.size(); ++i) {
    r.j["runs"].push_back({{"saved", saved[i]},
                           {"coverage", share(c.covered_pixels[i])},
                           {"psnr", number(c.psnr[i])},
                           {"psnr_exposure_matched", number(c.psnr_exposure_matched[i])},
                           {"ssim", c.ssim[i]}});
    r.table += table_row(saved[i], "PSNR " + fmt(c.psnr[i], 4) + " dB (exposure matched " +
                                       fmt(c.psnr_exposure_matched[i], 4) + " dB)  SSIM " + fmt(c.ssim[i], 4) +
                                       "  coverage " + fmt(share(c.covered_pixels[i]), 4));
  }
  add_regions(r, "worst_tiles", "tile", c.worst_tiles);
  add_regions(r, "regions", "region", c.regions);
  return r;
}

#endif

void write_eval_report(const EvalReport& report, bool json_requested, const std::string& json_path) {
  if (json_requested && json_path.empty()) {
    std::cerr << report.table;
    std::cout << json_text(report.j) << "\n";
    return;
  }
  std::cout << report.table;
  if (!json_requested) return;
  // e.g. WS/eval/ of a pipeline workspace, which no stage creates
  if (fs::path(json_path).has_parent_path()) fs::create_directories(fs::path(json_path).parent_path());
  write_atomically(json_path, [&](const fs::path& tmp) {
    std::ofstream out(tmp);
    out << json_text(report.j) << "\n";
    if (!out) throw OutputError(json_path, "the evaluation report");
  });
}

}  // namespace hos::eval
