#include "pipeline/stages.h"

#include <filesystem>

#include "core/error.h"
#include "mvs/mvs_options.h"
#include "pipeline/output_checks.h"
#include "recon/recon_options.h"
#include "refine/refine_options.h"
#include "sfm/image_inputs.h"
#include "sfm/sfm_options.h"
#include "texture/texture_options.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

template <typename Options>
std::function<std::unique_ptr<StageConfig>()> typed_config(const char* section) {
  return [section] { return std::make_unique<TypedStageConfig<Options>>(section); };
}
void add_undistorted_workspace(Fingerprint& f, const StagePaths& p) {
  f.add_folder_contents(p.undistorted / "sparse");
  f.add_folder_listing(p.undistorted / "images");
}

}  // namespace

const std::vector<StageSpec>& pipeline_stages() {
  static const std::vector<StageSpec> kSpecs{
      {"sfm", "hos-sfm",
       [](const DriverOptions& o, const StagePaths& p) {
         std::vector<std::string> args{"--images", o.photos.string(), "--workspace", p.root.string()};
         if (!o.existing_model.empty()) args.insert(args.end(), {"--sparse", o.existing_model.string()});
         return args;
       },
       [](Fingerprint& f, const DriverOptions& o, const StagePaths& p) {
         // What hos-sfm reads: the photos (by content), not sidecars or notes.
         f.add_file_listing(o.photos,
                            sfm::list_photo_files(o.photos, pipeline_files_in_photos(o.photos, o.output, p.root)));
         if (!o.existing_model.empty()) f.add_folder_contents(o.existing_model);
       },
       [](const StagePaths& p) { return fs::exists(p.undistorted / "sparse") && fs::exists(p.sfm_report); },
       typed_config<sfm::SfmOptions>("sfm"), std::nullopt},
      {"mvs", "hos-mvs",
       [](const DriverOptions&, const StagePaths& p) {
         return std::vector<std::string>{"--workspace", p.undistorted.string(), "--output", p.points.string(),
                                         "--report",    p.mvs_report.string()};
       },
       [](Fingerprint& f, const DriverOptions&, const StagePaths& p) { add_undistorted_workspace(f, p); },
       [](const StagePaths& p) { return fs::exists(p.points); }, typed_config<mvs::MvsOptions>("mvs"),
       StageSplit{"depth", "fuse",
                  [](const StagePaths& p, const std::string& views) {
                    return std::vector<std::string>{"--workspace", p.undistorted.string(), "--views",
                                                    views,         "--depth-maps",         p.depth_maps.string()};
                  },
                  [](const StagePaths& p) {
                    return std::vector<std::string>{
                        "--workspace", p.undistorted.string(), "--fuse",   p.depth_maps.string(),
                        "--output",    p.points.string(),      "--report", p.mvs_report.string()};
                  },
                  /*fixed_parts=*/nullptr}},
      {"recon", "hos-recon",
       [](const DriverOptions&, const StagePaths& p) {
         return std::vector<std::string>{"--input",       p.points.string(), "--output",
                                         p.mesh.string(), "--report",        p.recon_report.string()};
       },
       [](Fingerprint& f, const DriverOptions&, const StagePaths& p) { f.add_file_contents(p.points); },
       [](const StagePaths& p) { return fs::exists(p.mesh); }, typed_config<recon::ReconOptions>("recon"),
       // Only recon.tiles fixes the tiles before the points exist; with 0
       // the plan follows the points and the budget, and the one job tiles
       // in turn when it must.
       StageSplit{"tiles", "join",
                  [](const StagePaths& p, const std::string& tile) {
                    return std::vector<std::string>{"--input", p.points.string(), "--tile",
                                                    tile,      "--tile-dir",      p.recon_tiles.string()};
                  },
                  [](const StagePaths& p) {
                    return std::vector<std::string>{
                        "--input",  p.points.string(), "--join-tiles", p.recon_tiles.string(),
                        "--output", p.mesh.string(),   "--report",     p.recon_report.string()};
                  },
                  [](const PipelineConfig& config) {
                    const auto* recon = stage_options<recon::ReconOptions>(config, "recon");
                    return recon ? recon->tiles : 0;
                  }}},
      {"refine", "hos-refine",
       [](const DriverOptions&, const StagePaths& p) {
         return std::vector<std::string>{"--workspace", p.undistorted.string(), "--mesh", p.mesh.string(),
                                         "--output",    p.refined_mesh.string()};
       },
       [](Fingerprint& f, const DriverOptions&, const StagePaths& p) {
         f.add_file_contents(p.mesh);
         add_undistorted_workspace(f, p);
       },
       [](const StagePaths& p) { return fs::exists(p.refined_mesh); }, typed_config<refine::RefineOptions>("refine"),
       std::nullopt},
      {"texture", "hos-texture",
       [](const DriverOptions&, const StagePaths& p) {
         return std::vector<std::string>{
             "--workspace", p.undistorted.string(),    "--mesh",   p.refined_mesh.string(),
             "--output",    p.textured_model.string(), "--report", p.texture_report.string(),
             "--geo",       p.sfm_report.string()};
       },
       [](Fingerprint& f, const DriverOptions&, const StagePaths& p) {
         f.add_file_contents(p.refined_mesh);
         add_undistorted_workspace(f, p);
         f.add_file_contents(p.sfm_report);  // the photos' GPS (--geo)
       },
       [](const StagePaths& p) { return fs::exists(p.textured_model); },
       typed_config<texture::TextureOptions>("texture"),
       StageSplit{"views", "atlas",
                  [](const StagePaths& p, const std::string& views) {
                    return std::vector<std::string>{
                        "--workspace", p.undistorted.string(), "--mesh", p.refined_mesh.string(), "--views", views,
                        "--view-data", p.view_data.string()};
                  },
                  [](const StagePaths& p) {
                    return std::vector<std::string>{
                        "--workspace",      p.undistorted.string(),    "--mesh",   p.refined_mesh.string(),
                        "--from-view-data", p.view_data.string(),      "--output", p.textured_model.string(),
                        "--report",         p.texture_report.string(), "--geo",    p.sfm_report.string()};
                  },
                  /*fixed_parts=*/nullptr}},
  };
  return kSpecs;
}

std::size_t stage_index(const std::string& name, const std::string& flag) {
  const auto& specs = pipeline_stages();
  for (std::size_t i = 0; i < specs.size(); ++i) {
    if (specs[i].name == name) return i;
  }
  throw ConfigError(flag + " " + name, "unknown stage; the stages are: " + stage_names_text(", "));
}

std::string stage_names_text(const std::string& separator) {
  std::string text;
  for (const StageSpec& spec : pipeline_stages()) text += (text.empty() ? "" : separator) + spec.name;
  return text;
}

}  // namespace hos::pipeline
