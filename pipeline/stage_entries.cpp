#include "pipeline/stage_entries.h"

#include "core/error.h"
#include "pipeline/stage_figures.h"

namespace hos::pipeline {
namespace fs = std::filesystem;

void add_undistorted_workspace(Fingerprint& f, const StagePaths& p) {
  f.add_folder_contents(p.undistorted / "sparse");
  f.add_folder_listing(p.undistorted / "images");
  // The photos' masks, undistorted as the images (absent without masks, so
  // such workspaces keep their fingerprint).
  std::error_code ec;
  if (fs::exists(p.undistorted / "masks", ec)) f.add_folder_contents(p.undistorted / "masks");
}

std::uintmax_t size_of(const fs::path& path) {
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) return fs::file_size(path, ec);
  std::uintmax_t total = 0;
  for (auto it = fs::recursive_directory_iterator(path, fs::directory_options::skip_permission_denied, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (it->is_regular_file(ec)) total += it->file_size(ec);
  }
  return total;
}

std::optional<sfm::SfmReport> written_sfm_report(const StagePaths& paths) {
  try {
    return sfm::read_sfm_report(paths.sfm_report);
  } catch (const InputError&) {
    return std::nullopt;
  }
}

std::string figure_text(const nlohmann::ordered_json& figures, const char* key) {
  return figures.contains(key) ? figures[key].dump() : std::string("?");
}

void add_mesh_figures(const fs::path& mesh, nlohmann::ordered_json& figures) {
  auto counts = ply_element_counts(mesh);
  figures["vertices"] = counts["vertex"];
  figures["faces"] = counts["face"];
}

std::string mesh_figures_text(const nlohmann::ordered_json& figures) {
  return figure_text(figures, "vertices") + " vertices, " + figure_text(figures, "faces") + " faces";
}

}  // namespace hos::pipeline
