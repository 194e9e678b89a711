// hos-eval: the measurements of eval/ from the command line, as a table and JSON
// (eval/eval_report.h); the numeric options go through eval/eval_options.h.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "apps/stage_main.h"
#include "core/colmap_io.h"
#include "core/error.h"
#include "core/exit_codes.h"
#include "core/option_set.h"
#include "core/ply_io.h"
#include "eval/alignment.h"
#include "eval/curvature.h"
#include "eval/eval_options.h"
#include "eval/eval_report.h"
#include "eval/gltf_reader.h"
#include "eval/mesh_sanity.h"
#include "eval/surface_distance.h"
#ifdef HOS_EVAL_HAS_RENDER
#include "eval/render_compare.h"
#include "eval/visible_surface.h"
#endif

namespace fs = std::filesystem;
using hos::eval::EvalReport;

namespace {

hos::TriangleMesh read_surface(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".glb") return hos::eval::read_glb(path).mesh;
  if (ext == ".ply") return hos::read_mesh_ply(path);
  throw hos::InputError(path, "unknown extension (expected .ply or .glb)");
}

// --json on every subcommand: FILE, or stdout when no FILE.
struct JsonFlag {
  std::vector<CLI::Option*> options;  // one per subcommand
  std::string path;

  void add(CLI::App* sub) {
    options.push_back(sub->add_option("--json", path, "write JSON to FILE (or stdout when no FILE)")->expected(0, 1));
  }
  bool requested() const {
    return std::any_of(options.begin(), options.end(), [](CLI::Option* o) { return o->count() > 0; });
  }
};

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

// mesh: accuracy, completeness, Chamfer, F-score against a true mesh.
struct MeshCommand {
  CLI::App* cmd = nullptr;
  std::string result_path, truth_path, visible_model;
  hos::eval::MeshEvalOptions options;
  hos::OptionSet table{"eval"};
  hos::apps::CommonStageFlags flags;  // the table's flags as given
  AlignFlags align;

  void add(CLI::App& app, JsonFlag& json) {
    cmd = app.add_subcommand("mesh", "accuracy, completeness, Chamfer, F-score against a true mesh");
    cmd->add_option("--result", result_path, "result mesh or points (.ply, .glb)")->required();
    cmd->add_option("--truth", truth_path, "true mesh (.ply)")->required();
    cmd->add_option("--visible-in", visible_model,
                    "truth-frame sparse model: compare only with the true surface its cameras see");
    register_options(table, options);
    hos::apps::add_option_flags(*cmd, flags, table);
    align.add(cmd);
    json.add(cmd);
  }

  // The part of the truth that at least options.visible_min_views cameras see.
  void keep_visible_truth(hos::TriangleMesh& truth, EvalReport& r, hos::Reporter& reporter) const {
#ifdef HOS_EVAL_HAS_RENDER
    const std::size_t all_faces = truth.num_faces();
    truth = hos::eval::visible_part(truth, hos::read_colmap_model(visible_model), options.visible_min_views, reporter);
    hos::eval::add_visible_truth(truth.num_faces(), all_faces, options.visible_min_views, r);
#else
    throw hos::ConfigError("--visible-in", "hos-eval was built without the render module");
#endif
  }

  EvalReport run(hos::Reporter& reporter) {
    hos::apps::apply_config_and_overrides(table, flags);
    hos::eval::resolve_thresholds(options);
    EvalReport r;
    hos::TriangleMesh result = read_surface(result_path);
    hos::TriangleMesh truth = read_surface(truth_path);
    r.table += "mesh: " + result_path + " vs " + truth_path + "\n";
    if (!visible_model.empty()) keep_visible_truth(truth, r, reporter);
    if (const auto alignment = align.compute()) {
      r.j["alignment"] = hos::eval::alignment_report(*alignment, r);
      hos::eval::transform_mesh(result, alignment->truth_from_recovered);
    }
    hos::eval::add_surface_comparison(hos::eval::compare_surfaces(result, truth, options.distance, reporter), r);
    return r;
  }
};

// curvature: the Table 1 figures of the paper.
struct CurvatureCommand {
  CLI::App* cmd = nullptr;
  std::string mesh_path, points_path;

  void add(CLI::App& app, JsonFlag& json) {
    cmd = app.add_subcommand("curvature", "Table 1 figures: triangles, RMS point distance, |H|, |K|");
    cmd->add_option("--mesh", mesh_path, "mesh (.ply, .glb)")->required();
    cmd->add_option("--points", points_path, "input points (.ply) for the RMS distance");
    json.add(cmd);
  }

  EvalReport run(hos::Reporter& reporter) const {
    const hos::TriangleMesh mesh = read_surface(mesh_path);
    std::vector<Eigen::Vector3f> points;
    if (!points_path.empty()) points = hos::read_point_cloud_ply(points_path).positions;
    return hos::eval::curvature_report(
        hos::eval::compute_curvature_stats(mesh, points_path.empty() ? nullptr : &points, reporter), mesh_path);
  }
};

// sanity: topology of a mesh.
struct SanityCommand {
  CLI::App* cmd = nullptr;
  std::string mesh_path;

  void add(CLI::App& app, JsonFlag& json) {
    cmd = app.add_subcommand("sanity", "watertight, manifold, oriented, components, Euler characteristic");
    cmd->add_option("--mesh", mesh_path, "mesh (.ply, .glb)")->required();
    json.add(cmd);
  }

  EvalReport run(hos::Reporter& /*reporter*/) const {
    return hos::eval::sanity_report(hos::eval::check_mesh_sanity(read_surface(mesh_path)), mesh_path);
  }
};

// cameras: pose errors after a similarity alignment.
struct CamerasCommand {
  CLI::App* cmd = nullptr;
  std::string model, truth;

  void add(CLI::App& app, JsonFlag& json) {
    cmd = app.add_subcommand("cameras", "camera pose errors after a similarity alignment");
    cmd->add_option("--model", model, "recovered sparse model folder")->required();
    cmd->add_option("--truth", truth, "true sparse model folder")->required();
    json.add(cmd);
  }

  EvalReport run(hos::Reporter& /*reporter*/) const {
    return hos::eval::cameras_report(
        hos::eval::compare_camera_poses(hos::read_colmap_model(model), hos::read_colmap_model(truth)), model, truth);
  }
};

// render: PSNR/SSIM of a textured .glb re-rendered from a model's cameras.
struct RenderCommand {
  CLI::App* cmd = nullptr;
  std::string glb_path, model, images_dir, save_dir;
  AlignFlags align;

  void add(CLI::App& app, JsonFlag& json) {
    cmd = app.add_subcommand("render", "PSNR/SSIM of a textured .glb re-rendered from a model's cameras");
    cmd->add_option("--glb", glb_path, "textured mesh (.glb)")->required();
    cmd->add_option("--model", model, "sparse model whose cameras render (PINHOLE)")->required();
    cmd->add_option("--images", images_dir, "folder of the model's photos")->required();
    cmd->add_option("--save", save_dir, "write each render beside its photo as DIR/NAME.png");
    align.add(cmd);
    json.add(cmd);
  }

  EvalReport run(hos::Reporter& reporter) const {
#ifdef HOS_EVAL_HAS_RENDER
    EvalReport r;
    hos::render::RenderObject object = hos::eval::read_glb(glb_path);
    r.table += "render: " + glb_path + " vs " + images_dir + "\n";
    if (const auto alignment = align.compute()) {
      r.j["alignment"] = hos::eval::alignment_report(*alignment, r);
      hos::eval::transform_mesh(object.mesh, alignment->truth_from_recovered);
    }
    hos::eval::add_render_comparison(
        hos::eval::compare_renders(object, hos::read_colmap_model(model), images_dir, reporter, save_dir), r);
    return r;
#else
    throw hos::ConfigError("render", "hos-eval was built without the render module");
#endif
  }
};

#ifdef HOS_EVAL_HAS_RENDER
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
#endif

// common: several runs' saved renders of one view, compared with the photo
// over the pixels every run covers.
struct CommonCommand {
  CLI::App* cmd = nullptr;
  std::vector<std::string> saved;
  std::vector<std::string> regions;
  std::string crops_dir;
#ifdef HOS_EVAL_HAS_RENDER
  hos::eval::CommonOptions options;
#endif
  hos::OptionSet table{"eval"};
  hos::apps::CommonStageFlags flags;  // the table's flags as given

  void add(CLI::App& app, JsonFlag& json) {
    cmd = app.add_subcommand("common", "PSNR/SSIM of several runs' renders of one view over the pixels all cover");
    cmd->add_option("--saved", saved, "views saved by 'render --save' (DIR/NAME.png), one per run, same photo")
        ->required();
#ifdef HOS_EVAL_HAS_RENDER
    register_options(table, options);
    hos::apps::add_option_flags(*cmd, flags, table);
#endif
    cmd->add_option("--region", regions,
                    "X,Y,WIDTH,HEIGHT: also measure this rectangle of the photo (a thin structure; repeatable)");
    cmd->add_option("--crops", crops_dir,
                    "write DIR/tile_X_Y.png and DIR/region_X_Y_WxH.png for the listed tiles and regions: the photo "
                    "beside each run");
    json.add(cmd);
  }

  EvalReport run(hos::Reporter& /*reporter*/) {
#ifdef HOS_EVAL_HAS_RENDER
    hos::apps::apply_config_and_overrides(table, flags);
    options.crops_dir = crops_dir;
    for (const std::string& text : regions) options.regions.push_back(parse_region(text));
    return hos::eval::common_report(
        hos::eval::compare_on_common_pixels(std::vector<fs::path>(saved.begin(), saved.end()), options), saved);
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
  JsonFlag json;
  MeshCommand mesh;
  CurvatureCommand curvature;
  SanityCommand sanity;
  CamerasCommand cameras;
  RenderCommand render;
  CommonCommand common;
  mesh.add(app, json);
  curvature.add(app, json);
  sanity.add(app, json);
  cameras.add(app, json);
  render.add(app, json);
  common.add(app, json);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? hos::kExitSuccess : hos::kExitUsage;
  }
  return hos::apps::run_stage_main("eval", flags, [&](hos::Reporter& reporter) {
    EvalReport r;
    if (mesh.cmd->parsed()) r = mesh.run(reporter);
    if (curvature.cmd->parsed()) r = curvature.run(reporter);
    if (sanity.cmd->parsed()) r = sanity.run(reporter);
    if (cameras.cmd->parsed()) r = cameras.run(reporter);
    if (render.cmd->parsed()) r = render.run(reporter);
    if (common.cmd->parsed()) r = common.run(reporter);
    // Names the measurement in the file, e.g. for the run report's eval/*.json tables.
    r.j["command"] = app.get_subcommands().front()->get_name();
    hos::eval::write_eval_report(r, json.requested(), json.path);
  });
}
