#include "texture/texture_report.h"

#include "core/json_report.h"

namespace hos::texture {

namespace {

nlohmann::ordered_json vector_json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::ordered_json placement_json(const Placement& p) {
  nlohmann::ordered_json j;
  j["up"] = vector_json(p.up.up);
  j["up_method"] = up_method_name(p.up.method);
  if (!p.up.fallback_reason.empty()) j["up_fallback_reason"] = p.up.fallback_reason;
  j["x_axis_eigenvalues"] = vector_json(p.up.x_axis_eigenvalues);
  j["scale"] = p.scale;
  j["metric"] = p.metric;
  j["units"] = p.units;
  j["units_text"] = p.units_text();
  if (p.gps) {
    const GeoAlignment& g = *p.gps;
    j["gps"] = {{"usable", g.usable},
                {"reason", g.reason},
                {"photos", g.photos_with_gps},
                {"inliers", g.inliers},
                {"spread_m", g.spread_m},
                {"rms_residual_m", g.rms_residual_m},
                {"vertical_from_gps", g.vertical_from_gps},
                {"tilt_uncertainty_deg", g.tilt_uncertainty_deg}};
  }
  if (p.geo_origin) {
    j["geo_origin"] = {{"latitude_deg", p.geo_origin->latitude_deg}, {"longitude_deg", p.geo_origin->longitude_deg}};
    if (p.geo_origin->altitude_m) j["geo_origin"]["altitude_m"] = *p.geo_origin->altitude_m;
  }
  return j;
}

}  // namespace

nlohmann::ordered_json texture_report_json(const TextureResult& result) {
  const TextureStats& s = result.stats;
  nlohmann::ordered_json atlases = nlohmann::ordered_json::array();
  for (const auto& [w, h] : s.atlas_sizes) atlases.push_back({w, h});
  nlohmann::ordered_json gains = nlohmann::ordered_json::array();
  for (const auto& g : s.exposure_gains) gains.push_back(vector_json(g.cast<double>()));
  nlohmann::ordered_json steps;
  for (const auto& [step, seconds] : s.step_seconds) steps[step] = seconds;
  return {{"input_faces", s.input_faces},
          {"faces", s.faces},
          {"views", s.num_views},
          {"visible_face_view_pairs", s.num_candidates},
          {"outlier_rejections", s.num_outlier_rejections},
          {"unseen_faces", s.num_unseen_faces},
          {"charts", s.num_charts},
          {"merged_charts", s.num_merged_charts},
          {"atlases", atlases},
          {"texel_scale", s.texel_scale},
          {"atlas_coverage", s.atlas_coverage},
          {"seam_vertices", s.num_seam_vertices},
          {"mean_seam_jump_before", s.mean_seam_jump_before},
          {"mean_seam_jump_after", s.mean_seam_jump_after},
          {"seam_jumps_before", histogram_json(s.seam_jumps_before)},
          {"seam_jumps_after", histogram_json(s.seam_jumps_after)},
          {"views_per_face", histogram_json(s.views_per_face)},
          {"exposure_gains", gains},
          {"estimated_up", vector_json(s.estimated_up)},
          // Column-major, as in the glTF node.
          {"root_matrix", std::vector<double>(result.mesh.root_matrix.data(), result.mesh.root_matrix.data() + 16)},
          {"placement", placement_json(result.placement)},
          {"step_seconds", steps}};
}

void write_texture_report(const std::filesystem::path& path, const TextureResult& result) {
  write_json_report(path, texture_report_json(result));
}

}  // namespace hos::texture
