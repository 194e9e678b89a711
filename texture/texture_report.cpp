#include "texture/texture_report.h"

#include "core/json_report.h"

namespace hos::texture {

nlohmann::ordered_json texture_report_json(const TextureResult& result) {
  const TextureStats& s = result.stats;
  nlohmann::ordered_json j;
  j["input_faces"] = s.input_faces;
  j["faces"] = s.faces;
  j["views"] = s.num_views;
  j["visible_face_view_pairs"] = s.num_candidates;
  j["outlier_rejections"] = s.num_outlier_rejections;
  j["unseen_faces"] = s.num_unseen_faces;
  j["charts"] = s.num_charts;
  nlohmann::ordered_json atlases = nlohmann::ordered_json::array();
  for (const auto& [w, h] : s.atlas_sizes) atlases.push_back({w, h});
  j["atlases"] = atlases;
  j["texel_scale"] = s.texel_scale;
  j["seam_vertices"] = s.num_seam_vertices;
  j["mean_seam_jump_before"] = s.mean_seam_jump_before;
  j["mean_seam_jump_after"] = s.mean_seam_jump_after;
  j["seam_jumps_before"] = histogram_json(s.seam_jumps_before);
  j["seam_jumps_after"] = histogram_json(s.seam_jumps_after);
  j["views_per_face"] = histogram_json(s.views_per_face);
  nlohmann::ordered_json gains = nlohmann::ordered_json::array();
  for (const auto& g : s.exposure_gains) gains.push_back({g.x(), g.y(), g.z()});
  j["exposure_gains"] = gains;
  j["estimated_up"] = {s.estimated_up.x(), s.estimated_up.y(), s.estimated_up.z()};
  // Column-major, as in the glTF node.
  j["root_matrix"] = std::vector<double>(result.mesh.root_matrix.data(), result.mesh.root_matrix.data() + 16);
  nlohmann::ordered_json steps;
  for (const auto& [step, seconds] : s.step_seconds) steps[step] = seconds;
  j["step_seconds"] = steps;
  return j;
}

void write_texture_report(const std::filesystem::path& path, const TextureResult& result) {
  write_json_report(path, texture_report_json(result));
}

}  // namespace hos::texture
