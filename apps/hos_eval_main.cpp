// hos-eval: the measurements of eval/ from the command line, as a table and JSON.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/atomic_file.h"
#include "core/colmap_io.h"
#include "core/error.h"
#include "core/exit_codes.h"
#include "core/json_report.h"
#include "core/ply_io.h"
#include "eval/alignment.h"
#if HOS_EVAL_HAS_RENDER
#include "eval/visible_surface.h"
#endif
#include "apps/stage_main.h"
#include "eval/curvature.h"
#include "eval/gltf_reader.h"
#include "eval/mesh_sanity.h"
#include "eval/surface_distance.h"
#ifdef HOS_EVAL_HAS_RENDER
#include "eval/render_compare.h"
#endif

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// JSON has no infinity: +inf (identical images) is written as null.
[[maybe_unused]] json number(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

hos::TriangleMesh read_surface(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".glb") return hos::eval::read_glb(path).mesh;
  if (ext == ".ply") return hos::read_mesh_ply(path);
  throw hos::InputError(path, "unknown extension (expected .ply or .glb)");
}

json to_json(const hos::eval::Similarity3& s) {
  json j;
  j["scale"] = s.scale;
  j["rotation"] = {
      {s.R(0, 0), s.R(0, 1), s.R(0, 2)}, {s.R(1, 0), s.R(1, 1), s.R(1, 2)}, {s.R(2, 0), s.R(2, 1), s.R(2, 2)}};
  j["translation"] = {s.t.x(), s.t.y(), s.t.z()};
  return j;
}

json to_json(const hos::eval::DistanceStats& d) {
  return {{"mean", d.mean}, {"median", d.median}, {"p90", d.p90}, {"rms", d.rms}, {"max", d.max}, {"count", d.count}};
}

std::vector<double> parse_thresholds(const std::string& text) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      std::size_t used = 0;
      out.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw hos::ConfigError("eval.thresholds", "'" + item + "' is not a number");
    }
  }
  return out;
}

// Where the report goes: --json FILE writes the file and prints the table;
// a bare --json prints JSON on stdout and the table on stderr.
struct Output {
  std::vector<CLI::Option*> json_options;  // one per subcommand
  std::string json_path;

  // Adds --json to a subcommand.
  void add_json(CLI::App* sub) {
    json_options.push_back(
        sub->add_option("--json", json_path, "write JSON to FILE (or stdout when no FILE)")->expected(0, 1));
  }

  void emit(const json& j, const std::string& table) const {
    const bool json_requested =
        std::any_of(json_options.begin(), json_options.end(), [](CLI::Option* o) { return o->count() > 0; });
    if (json_requested && json_path.empty()) {
      std::cerr << table;
      std::cout << hos::json_text(j) << "\n";
      return;
    }
    std::cout << table;
    if (json_requested) {
      // e.g. WS/eval/ of a pipeline workspace, which no stage creates
      if (fs::path(json_path).has_parent_path()) fs::create_directories(fs::path(json_path).parent_path());
      hos::write_atomically(json_path, [&](const fs::path& tmp) {
        std::ofstream out(tmp);
        out << hos::json_text(j) << "\n";
        if (!out) throw hos::OutputError(json_path, "could not write");
      });
    }
  }
};

std::string row(const std::string& name, const std::string& value) {
  std::ostringstream s;
  s << "  " << std::left << std::setw(34) << name << value << "\n";
  return s.str();
}

std::string fmt(double x, int precision = 6) {
  std::ostringstream s;
  s << std::setprecision(precision) << x;
  return s.str();
}

// Optional alignment of a result given in the recovered model's frame.
struct AlignFlags {
  std::string recovered_model, truth_model;
  void add(CLI::App* app) {
    app->add_option("--align-model", recovered_model, "sparse model the result's coordinates belong to");
    app->add_option("--truth-model", truth_model, "ground-truth sparse model (same image names)");
  }
  std::optional<hos::eval::ModelAlignment> compute() const {
    if (recovered_model.empty() != truth_model.empty()) {
      throw hos::ConfigError("--align-model/--truth-model", "give both or neither");
    }
    if (recovered_model.empty()) return std::nullopt;
    return hos::eval::align_models_by_image_name(hos::read_colmap_model(recovered_model),
                                                 hos::read_colmap_model(truth_model));
  }
};

json alignment_json(const hos::eval::ModelAlignment& a, std::string& table) {
  table += row("aligned cameras", std::to_string(a.names.size()));
  table += row("alignment scale", fmt(a.truth_from_recovered.scale));
  table += row("alignment RMS residual", fmt(a.rms_residual));
  json j = to_json(a.truth_from_recovered);
  j["cameras"] = a.names.size();
  j["rms_residual"] = a.rms_residual;
  return j;
}

// The figures of one subcommand: JSON and a human-readable table.
struct Report {
  json j;
  std::string table;
};

// mesh: accuracy, completeness, Chamfer, F-score against a true mesh.
struct MeshCommand {
  CLI::App* cmd = nullptr;
  std::string result_path, truth_path, thresholds_text = "0.005,0.01,0.02";
  hos::eval::SurfaceDistanceOptions distance_options;
  std::string visible_model;
  int visible_min_views = 2;
  AlignFlags align;

  void add(CLI::App& app, Output& output) {
    cmd = app.add_subcommand("mesh", "accuracy, completeness, Chamfer, F-score against a true mesh");
    cmd->add_option("--result", result_path, "result mesh or points (.ply, .glb)")->required();
    cmd->add_option("--truth", truth_path, "true mesh (.ply)")->required();
    cmd->add_option("--thresholds", thresholds_text, "F-score thresholds as fractions of the truth's bbox diagonal");
    cmd->add_option("--samples", distance_options.num_samples, "surface samples per mesh");
    cmd->add_option("--seed", distance_options.seed, "sampling seed");
    cmd->add_option("--visible-in", visible_model,
                    "truth-frame sparse model: compare only with the true surface its cameras see");
    cmd->add_option("--min-views", visible_min_views, "views that must see a true face (with --visible-in)");
    align.add(cmd);
    output.add_json(cmd);
  }

  // The part of the truth that at least visible_min_views cameras see.
  void keep_visible_truth(hos::TriangleMesh& truth, Report& r, hos::Reporter& reporter) const {
#if HOS_EVAL_HAS_RENDER
    const std::size_t all_faces = truth.num_faces();
    truth = hos::eval::visible_part(truth, hos::read_colmap_model(visible_model), visible_min_views, reporter);
    r.j["truth_faces_visible"] = truth.num_faces();
    r.table += row("true faces seen by >= " + std::to_string(visible_min_views) + " views",
                   std::to_string(truth.num_faces()) + " of " + std::to_string(all_faces));
#else
    throw hos::ConfigError("--visible-in", "hos-eval was built without the render module");
#endif
  }

  Report run(hos::Reporter& reporter) {
    distance_options.thresholds = parse_thresholds(thresholds_text);
    distance_options.validate();
    Report r;
    hos::TriangleMesh result = read_surface(result_path);
    hos::TriangleMesh truth = read_surface(truth_path);
    r.table += "mesh: " + result_path + " vs " + truth_path + "\n";
    if (!visible_model.empty()) keep_visible_truth(truth, r, reporter);
    if (const auto alignment = align.compute()) {
      r.j["alignment"] = alignment_json(*alignment, r.table);
      hos::eval::transform_mesh(result, alignment->truth_from_recovered);
    }
    const hos::eval::SurfaceComparison c = hos::eval::compare_surfaces(result, truth, distance_options, reporter);
    r.j["truth_diagonal"] = c.truth_diagonal;
    r.j["result_is_points"] = c.result_is_points;
    r.j["accuracy"] = to_json(c.accuracy);
    r.j["completeness"] = to_json(c.completeness);
    r.j["chamfer"] = c.chamfer;
    r.j["f_score"] = c.primary().f_score;
    r.j["f_score_threshold"] = c.primary().fraction;
    r.j["thresholds"] = json::array();
    r.table += row("truth bbox diagonal", fmt(c.truth_diagonal));
    r.table += row("accuracy mean/median/p90",
                   fmt(c.accuracy.mean) + " / " + fmt(c.accuracy.median) + " / " + fmt(c.accuracy.p90));
    r.table += row("completeness mean/median/p90",
                   fmt(c.completeness.mean) + " / " + fmt(c.completeness.median) + " / " + fmt(c.completeness.p90));
    r.table += row("chamfer", fmt(c.chamfer));
    for (const auto& s : c.scores) {
      r.j["thresholds"].push_back({{"fraction", s.fraction},
                                   {"distance", s.distance},
                                   {"precision", s.precision},
                                   {"recall", s.recall},
                                   {"f_score", s.f_score}});
      r.table += row("P/R/F @ " + fmt(100.0 * s.fraction, 3) + "% diag",
                     fmt(s.precision, 4) + " / " + fmt(s.recall, 4) + " / " + fmt(s.f_score, 4));
    }
    return r;
  }
};

// curvature: the Table 1 figures of the paper.
struct CurvatureCommand {
  CLI::App* cmd = nullptr;
  std::string mesh_path, points_path;

  void add(CLI::App& app, Output& output) {
    cmd = app.add_subcommand("curvature", "Table 1 figures: triangles, RMS point distance, |H|, |K|");
    cmd->add_option("--mesh", mesh_path, "mesh (.ply, .glb)")->required();
    cmd->add_option("--points", points_path, "input points (.ply) for the RMS distance");
    output.add_json(cmd);
  }

  Report run(hos::Reporter& reporter) const {
    const hos::TriangleMesh mesh = read_surface(mesh_path);
    std::vector<Eigen::Vector3f> points;
    if (!points_path.empty()) points = hos::read_point_cloud_ply(points_path).positions;
    const hos::eval::CurvatureStats s =
        hos::eval::compute_curvature_stats(mesh, points_path.empty() ? nullptr : &points, reporter);
    Report r;
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
    r.table += row("triangles", std::to_string(s.triangles));
    r.table += row("RMS points -> surface", s.rms_point_distance ? fmt(*s.rms_point_distance) : "-");
    r.table += row("avg / max |H|", fmt(s.mean_abs_h) + " / " + fmt(s.max_abs_h));
    r.table += row("avg / max |K|", fmt(s.mean_abs_k) + " / " + fmt(s.max_abs_k));
    r.table += row("p99 |H| / |K|", fmt(s.p99_abs_h) + " / " + fmt(s.p99_abs_k));
    return r;
  }
};

// sanity: topology of a mesh.
struct SanityCommand {
  CLI::App* cmd = nullptr;
  std::string mesh_path;

  void add(CLI::App& app, Output& output) {
    cmd = app.add_subcommand("sanity", "watertight, manifold, oriented, components, Euler characteristic");
    cmd->add_option("--mesh", mesh_path, "mesh (.ply, .glb)")->required();
    output.add_json(cmd);
  }

  Report run(hos::Reporter& /*reporter*/) const {
    const hos::eval::MeshSanity s = hos::eval::check_mesh_sanity(read_surface(mesh_path));
    Report r;
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
    for (const auto& [key, value] : r.j.items()) r.table += row(key, value.dump());
    return r;
  }
};

// cameras: pose errors after a similarity alignment.
struct CamerasCommand {
  CLI::App* cmd = nullptr;
  std::string model, truth;

  void add(CLI::App& app, Output& output) {
    cmd = app.add_subcommand("cameras", "camera pose errors after a similarity alignment");
    cmd->add_option("--model", model, "recovered sparse model folder")->required();
    cmd->add_option("--truth", truth, "true sparse model folder")->required();
    output.add_json(cmd);
  }

  Report run(hos::Reporter& /*reporter*/) const {
    const hos::eval::CameraPoseComparison c =
        hos::eval::compare_camera_poses(hos::read_colmap_model(model), hos::read_colmap_model(truth));
    Report r;
    r.j["alignment"] = to_json(c.truth_from_recovered);
    r.j["scene_size"] = c.scene_size;
    r.j["images_recovered"] = c.num_recovered;
    r.j["images_truth"] = c.num_truth;
    r.j["images_matched"] = c.cameras.size();
    r.j["center_error"] = {
        {"mean", c.mean_center_error}, {"median", c.median_center_error}, {"max", c.max_center_error}};
    r.j["rotation_error_deg"] = {{"mean", c.mean_rotation_error_deg},
                                 {"median", c.median_rotation_error_deg},
                                 {"max", c.max_rotation_error_deg}};
    r.j["cameras"] = json::array();
    for (const auto& e : c.cameras) {
      r.j["cameras"].push_back(
          {{"name", e.name}, {"center_error", e.center_error}, {"rotation_error_deg", e.rotation_error_deg}});
    }
    r.table += "cameras: " + model + " vs " + truth + "\n";
    r.table +=
        row("matched / recovered / truth", std::to_string(c.cameras.size()) + " / " + std::to_string(c.num_recovered) +
                                               " / " + std::to_string(c.num_truth));
    r.table += row("alignment scale", fmt(c.truth_from_recovered.scale));
    r.table +=
        row("centre error mean/median/max", fmt(c.mean_center_error) + " / " + fmt(c.median_center_error) + " / " +
                                                fmt(c.max_center_error) + " (x scene size " + fmt(c.scene_size) + ")");
    r.table += row("rotation error mean/median/max", fmt(c.mean_rotation_error_deg) + " / " +
                                                         fmt(c.median_rotation_error_deg) + " / " +
                                                         fmt(c.max_rotation_error_deg) + " deg");
    return r;
  }
};

// render: PSNR/SSIM of a textured .glb re-rendered from a model's cameras.
struct RenderCommand {
  CLI::App* cmd = nullptr;
  std::string glb_path, model, images_dir, save_dir;
  AlignFlags align;

  void add(CLI::App& app, Output& output) {
    cmd = app.add_subcommand("render", "PSNR/SSIM of a textured .glb re-rendered from a model's cameras");
    cmd->add_option("--glb", glb_path, "textured mesh (.glb)")->required();
    cmd->add_option("--model", model, "sparse model whose cameras render (PINHOLE)")->required();
    cmd->add_option("--images", images_dir, "folder of the model's photos")->required();
    cmd->add_option("--save", save_dir, "write each render beside its photo as DIR/NAME.png");
    align.add(cmd);
    output.add_json(cmd);
  }

  Report run(hos::Reporter& reporter) const {
#ifdef HOS_EVAL_HAS_RENDER
    Report r;
    hos::render::RenderObject object = hos::eval::read_glb(glb_path);
    r.table += "render: " + glb_path + " vs " + images_dir + "\n";
    if (const auto alignment = align.compute()) {
      r.j["alignment"] = alignment_json(*alignment, r.table);
      hos::eval::transform_mesh(object.mesh, alignment->truth_from_recovered);
    }
    const hos::eval::RenderComparison c =
        hos::eval::compare_renders(object, hos::read_colmap_model(model), images_dir, reporter, save_dir);
    r.j["mean_psnr"] = number(c.mean_psnr);
    r.j["mean_ssim"] = c.mean_ssim;
    r.j["skipped_views"] = c.skipped_views;
    r.j["views"] = json::array();
    for (const auto& v : c.views) {
      r.j["views"].push_back(
          {{"name", v.name}, {"mask_pixels", v.mask_pixels}, {"psnr", number(v.psnr)}, {"ssim", v.ssim}});
      r.table += row(v.name, "PSNR " + fmt(v.psnr, 4) + " dB  SSIM " + fmt(v.ssim, 4));
    }
    r.table += row("mean", "PSNR " + fmt(c.mean_psnr, 4) + " dB  SSIM " + fmt(c.mean_ssim, 4));
    return r;
#else
    throw hos::ConfigError("render", "hos-eval was built without the render module");
#endif
  }
};

// X,Y,WIDTH,HEIGHT of --region.
hos::eval::PixelRect parse_region(const std::string& text) {
  hos::eval::PixelRect r;
  char c1 = 0, c2 = 0, c3 = 0;
  std::istringstream in(text);
  if (!(in >> r.x >> c1 >> r.y >> c2 >> r.width >> c3 >> r.height) || c1 != ',' || c2 != ',' || c3 != ',' ||
      !(in >> std::ws).eof()) {
    throw hos::ConfigError("--region " + text, "expected X,Y,WIDTH,HEIGHT in pixels");
  }
  return r;
}

// Tiles or regions as JSON (key) and table rows (name X,Y[,WxH]).
void add_regions(Report& r,
                 const std::string& key,
                 const std::string& name,
                 const std::vector<hos::eval::ErrorRegion>& regions) {
  r.j[key] = json::array();
  for (const hos::eval::ErrorRegion& e : regions) {
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
    r.table += row(label.str(), value.str());
  }
}

// common: several runs' saved renders of one view, compared with the photo
// over the pixels every run covers.
struct CommonCommand {
  CLI::App* cmd = nullptr;
  std::vector<std::string> saved;
  std::vector<std::string> regions;
  hos::eval::CommonOptions options;

  void add(CLI::App& app, Output& output) {
    cmd = app.add_subcommand("common", "PSNR/SSIM of several runs' renders of one view over the pixels all cover");
    cmd->add_option("--saved", saved, "views saved by 'render --save' (DIR/NAME.png), one per run, same photo")
        ->required();
    cmd->add_option("--worst-tiles", options.worst_tiles,
                    "list this many tiles of the photo, those carrying most of the first run's squared error first")
        ->default_val(0);
    cmd->add_option("--tile-size", options.tile_size, "tile side (pixels)")
        ->default_val(128)
        ->check(CLI::Range(1, 1 << 16));
    cmd->add_option("--region", regions,
                    "X,Y,WIDTH,HEIGHT: also measure this rectangle of the photo (a thin structure; repeatable)");
    cmd->add_option("--crops", options.crops_dir,
                    "write DIR/tile_X_Y.png and DIR/region_X_Y_WxH.png for the listed tiles and regions: the photo "
                    "beside each run");
    output.add_json(cmd);
  }

  Report run(hos::Reporter&) const {
#ifdef HOS_EVAL_HAS_RENDER
    Report r;
    hos::eval::CommonOptions with_regions = options;
    for (const std::string& text : regions) with_regions.regions.push_back(parse_region(text));
    const hos::eval::CommonComparison c =
        hos::eval::compare_on_common_pixels(std::vector<fs::path>(saved.begin(), saved.end()), with_regions);
    const auto share = [&](std::size_t pixels) { return static_cast<double>(pixels) / c.photo_pixels; };
    r.j["photo_pixels"] = c.photo_pixels;
    r.j["common_coverage"] = share(c.common_pixels);
    r.j["runs"] = json::array();
    r.table += row("common coverage", fmt(share(c.common_pixels), 4));
    for (std::size_t i = 0; i < saved.size(); ++i) {
      r.j["runs"].push_back({{"saved", saved[i]},
                             {"coverage", share(c.covered_pixels[i])},
                             {"psnr", number(c.psnr[i])},
                             {"psnr_exposure_matched", number(c.psnr_exposure_matched[i])},
                             {"ssim", c.ssim[i]}});
      r.table +=
          row(saved[i], "PSNR " + fmt(c.psnr[i], 4) + " dB (exposure matched " + fmt(c.psnr_exposure_matched[i], 4) +
                            " dB)  SSIM " + fmt(c.ssim[i], 4) + "  coverage " + fmt(share(c.covered_pixels[i]), 4));
    }
    add_regions(r, "worst_tiles", "tile", c.worst_tiles);
    add_regions(r, "regions", "region", c.regions);
    return r;
#else
    throw hos::ConfigError("common", "hos-eval was built without the render module");
#endif
  }
};

}  // namespace

int main(int argc, char** argv) {
  hos::apps::CommonStageFlags flags;
  flags.progress = "none";
  CLI::App app{"hos-eval: measure reconstructions against ground truth"};
  app.require_subcommand(1);
  app.add_option("--progress", flags.progress, "auto|bar|plain|json|none")->default_val("none");
  app.add_option("--log", flags.log_file, "log file");
  app.add_flag("--verbose", flags.verbose, "show debug messages");
  Output output;
  MeshCommand mesh;
  CurvatureCommand curvature;
  SanityCommand sanity;
  CamerasCommand cameras;
  RenderCommand render;
  CommonCommand common;
  mesh.add(app, output);
  curvature.add(app, output);
  sanity.add(app, output);
  cameras.add(app, output);
  render.add(app, output);
  common.add(app, output);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? hos::kExitSuccess : hos::kExitUsage;
  }
  return hos::apps::run_stage_main("eval", flags, [&](hos::Reporter& reporter) {
    Report r;
    if (mesh.cmd->parsed()) r = mesh.run(reporter);
    if (curvature.cmd->parsed()) r = curvature.run(reporter);
    if (sanity.cmd->parsed()) r = sanity.run(reporter);
    if (cameras.cmd->parsed()) r = cameras.run(reporter);
    if (render.cmd->parsed()) r = render.run(reporter);
    if (common.cmd->parsed()) r = common.run(reporter);
    // Names the measurement in the file, e.g. for the run report's eval/*.json tables.
    r.j["command"] = app.get_subcommands().front()->get_name();
    output.emit(r.j, r.table);
  });
}
