#include "texture/texture_report.h"

#include <algorithm>

#include "core/json_report.h"

namespace hos::texture {
namespace {

using Json = nlohmann::ordered_json;

Json vector_json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

Eigen::Vector3d vector_from_json(const Json& j) {
  const auto v = j.get<std::array<double, 3>>();
  return {v[0], v[1], v[2]};
}

void read_vector(const Json& j, const char* key, Eigen::Vector3d& v) {
  if (const auto it = j.find(key); it != j.end()) v = vector_from_json(*it);
}

GpsFitReport gps_fit_report(const GeoAlignment& g) {
  return {g.usable,   g.reason,         g.photos_with_gps,   g.inliers,
          g.spread_m, g.rms_residual_m, g.vertical_from_gps, g.tilt_uncertainty_deg};
}

PlacementReport placement_report(const Placement& p) {
  PlacementReport r;
  r.up = p.up.up;
  r.up_method = up_method_name(p.up.method);
  r.up_fallback_reason = p.up.fallback_reason;
  r.x_axis_eigenvalues = p.up.x_axis_eigenvalues;
  r.scale = p.scale;
  r.metric = p.metric;
  r.units = p.units;
  r.units_text = p.units_text();
  if (p.gps) r.gps = gps_fit_report(*p.gps);
  r.geo_origin = p.geo_origin;
  return r;
}

Json placement_json(const PlacementReport& p) {
  Json j;
  j["up"] = vector_json(p.up);
  j["up_method"] = p.up_method;
  if (!p.up_fallback_reason.empty()) j["up_fallback_reason"] = p.up_fallback_reason;
  j["x_axis_eigenvalues"] = vector_json(p.x_axis_eigenvalues);
  j["scale"] = p.scale;
  j["metric"] = p.metric;
  j["units"] = p.units;
  j["units_text"] = p.units_text;
  if (p.gps) {
    const GpsFitReport& g = *p.gps;
    j["gps"] = {{"usable", g.usable},
                {"reason", g.reason},
                {"photos", g.photos},
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

GpsFitReport gps_fit_from_json(const Json& j) {
  GpsFitReport g;
  read_key(j, "usable", g.usable);
  read_key(j, "reason", g.reason);
  read_key(j, "photos", g.photos);
  read_key(j, "inliers", g.inliers);
  read_key(j, "spread_m", g.spread_m);
  read_key(j, "rms_residual_m", g.rms_residual_m);
  read_key(j, "vertical_from_gps", g.vertical_from_gps);
  read_key(j, "tilt_uncertainty_deg", g.tilt_uncertainty_deg);
  return g;
}

GeoPosition geo_position_from_json(const Json& j) {
  GeoPosition g;
  read_key(j, "latitude_deg", g.latitude_deg);
  read_key(j, "longitude_deg", g.longitude_deg);
  if (const auto it = j.find("altitude_m"); it != j.end()) g.altitude_m = it->get<double>();
  return g;
}

PlacementReport placement_from_json(const Json& j) {
  PlacementReport p;
  read_vector(j, "up", p.up);
  read_key(j, "up_method", p.up_method);
  read_key(j, "up_fallback_reason", p.up_fallback_reason);
  read_vector(j, "x_axis_eigenvalues", p.x_axis_eigenvalues);
  read_key(j, "scale", p.scale);
  read_key(j, "metric", p.metric);
  read_key(j, "units", p.units);
  read_key(j, "units_text", p.units_text);
  if (const auto it = j.find("gps"); it != j.end()) p.gps = gps_fit_from_json(*it);
  if (const auto it = j.find("geo_origin"); it != j.end()) p.geo_origin = geo_position_from_json(*it);
  return p;
}

TextureReport report_from_json(const Json& j) {
  TextureReport r;
  read_key(j, "input_faces", r.input_faces);
  read_key(j, "faces", r.faces);
  read_key(j, "views", r.views);
  read_key(j, "visible_face_view_pairs", r.visible_face_view_pairs);
  read_key(j, "outlier_rejections", r.outlier_rejections);
  read_key(j, "unseen_faces", r.unseen_faces);
  read_key(j, "charts", r.charts);
  read_key(j, "merged_charts", r.merged_charts);
  read_key(j, "atlases", r.atlases);
  read_key(j, "texel_scale", r.texel_scale);
  read_key(j, "atlas_coverage", r.atlas_coverage);
  read_key(j, "seam_vertices", r.seam_vertices);
  read_key(j, "mean_seam_jump_before", r.mean_seam_jump_before);
  read_key(j, "mean_seam_jump_after", r.mean_seam_jump_after);
  read_key(j, "seam_jumps_before", r.seam_jumps_before);
  read_key(j, "seam_jumps_after", r.seam_jumps_after);
  read_key(j, "views_per_face", r.views_per_face);
  if (const auto it = j.find("exposure_gains"); it != j.end()) {
    for (const Json& gain : it->get<std::vector<Json>>()) r.exposure_gains.push_back(vector_from_json(gain));
  }
  read_vector(j, "estimated_up", r.estimated_up);
  read_key(j, "root_matrix", r.root_matrix);
  if (const auto it = j.find("placement"); it != j.end()) r.placement = placement_from_json(*it);
  read_key(j, "step_seconds", r.step_seconds);
  return r;
}

}  // namespace

TextureReport texture_report(const TextureResult& result) {
  const TextureStats& s = result.stats;
  TextureReport r;
  r.input_faces = static_cast<std::int64_t>(s.input_faces);
  r.faces = static_cast<std::int64_t>(s.faces);
  r.views = s.num_views;
  r.visible_face_view_pairs = s.num_candidates;
  r.outlier_rejections = s.num_outlier_rejections;
  r.unseen_faces = s.num_unseen_faces;
  r.charts = s.num_charts;
  r.merged_charts = s.num_merged_charts;
  r.atlases = s.atlas_sizes;
  r.texel_scale = s.texel_scale;
  r.atlas_coverage = s.atlas_coverage;
  r.seam_vertices = s.num_seam_vertices;
  r.mean_seam_jump_before = s.mean_seam_jump_before;
  r.mean_seam_jump_after = s.mean_seam_jump_after;
  r.seam_jumps_before = s.seam_jumps_before;
  r.seam_jumps_after = s.seam_jumps_after;
  r.views_per_face = s.views_per_face;
  for (const Eigen::Vector3f& gain : s.exposure_gains) r.exposure_gains.push_back(gain.cast<double>());
  r.estimated_up = s.estimated_up;
  std::copy(result.mesh.root_matrix.data(), result.mesh.root_matrix.data() + 16, r.root_matrix.begin());
  r.placement = placement_report(result.placement);
  r.step_seconds = s.step_seconds;
  return r;
}

nlohmann::ordered_json to_json(const TextureReport& r) {
  Json atlases = Json::array();
  for (const auto& [w, h] : r.atlases) atlases.push_back({w, h});
  Json gains = Json::array();
  for (const Eigen::Vector3d& g : r.exposure_gains) gains.push_back(vector_json(g));
  return {{"input_faces", r.input_faces},
          {"faces", r.faces},
          {"views", r.views},
          {"visible_face_view_pairs", r.visible_face_view_pairs},
          {"outlier_rejections", r.outlier_rejections},
          {"unseen_faces", r.unseen_faces},
          {"charts", r.charts},
          {"merged_charts", r.merged_charts},
          {"atlases", atlases},
          {"texel_scale", r.texel_scale},
          {"atlas_coverage", r.atlas_coverage},
          {"seam_vertices", r.seam_vertices},
          {"mean_seam_jump_before", r.mean_seam_jump_before},
          {"mean_seam_jump_after", r.mean_seam_jump_after},
          {"seam_jumps_before", histogram_json(r.seam_jumps_before)},
          {"seam_jumps_after", histogram_json(r.seam_jumps_after)},
          {"views_per_face", histogram_json(r.views_per_face)},
          {"exposure_gains", gains},
          {"estimated_up", vector_json(r.estimated_up)},
          {"root_matrix", r.root_matrix},
          {"placement", placement_json(r.placement)},
          {"step_seconds", named_values_json(r.step_seconds)}};
}

TextureReport read_texture_report(const std::filesystem::path& path) {
  return read_json_report(path, report_from_json);
}

void write_texture_report(const std::filesystem::path& path, const TextureResult& result) {
  write_json_report(path, to_json(texture_report(result)));
}

}  // namespace hos::texture
