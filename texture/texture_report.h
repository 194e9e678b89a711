// The texture stage's report (hos-texture --report FILE,
// WS/texture/report.json in a pipeline run) for the run report: counts,
// step times, exposure gains, seam jumps before and after leveling, views
// per face, the root-node matrix of the glTF and how the model was placed.
// Its JSON keys are in texture_report.cpp alone: the stage writes and the
// pipeline reads it through these functions.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/geodesy.h"
#include "core/histogram.h"
#include "texture/texture_mesh.h"

namespace hos::texture {

// The GPS fit of the placement (texture/geo_alignment.h).
struct GpsFitReport {
  bool usable = false;
  std::string reason;
  int photos = 0;  // registered photos with a GPS position
  int inliers = 0;
  double spread_m = 0.0;
  double rms_residual_m = 0.0;
  bool vertical_from_gps = false;
  double tilt_uncertainty_deg = 0.0;
};

// How the model was placed (texture/placement.h).
struct PlacementReport {
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  std::string up_method;           // up_method_name
  std::string up_fallback_reason;  // empty when the camera x axes decided (left out of the file)
  Eigen::Vector3d x_axis_eigenvalues = Eigen::Vector3d::Zero();
  double scale = 1.0;
  bool metric = false;
  std::string units;
  std::string units_text;  // Placement::units_text
  std::optional<GpsFitReport> gps;
  std::optional<GeoPosition> geo_origin;
};

struct TextureReport {
  std::int64_t input_faces = 0;
  std::int64_t faces = 0;
  int views = 0;
  std::int64_t visible_face_view_pairs = 0;
  std::int64_t outlier_rejections = 0;
  int unseen_faces = 0;
  int charts = 0;
  int merged_charts = 0;
  std::vector<std::pair<int, int>> atlases;  // width, height
  double texel_scale = 1.0;
  double atlas_coverage = 0.0;
  int seam_vertices = 0;
  double mean_seam_jump_before = 0.0;
  double mean_seam_jump_after = 0.0;
  Histogram seam_jumps_before, seam_jumps_after, views_per_face;
  std::vector<Eigen::Vector3d> exposure_gains;  // RGB per view
  Eigen::Vector3d estimated_up = Eigen::Vector3d::UnitY();
  std::array<double, 16> root_matrix{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // column-major, as in glTF
  PlacementReport placement;
  std::vector<std::pair<std::string, double>> step_seconds;  // in the order the steps ran
};

// The report of a run.
TextureReport texture_report(const TextureResult& result);

nlohmann::ordered_json to_json(const TextureReport& report);
// Throws InputError naming the file when it is missing or malformed.
TextureReport read_texture_report(const std::filesystem::path& path);

// Writes texture_report(result) atomically; throws OutputError.
void write_texture_report(const std::filesystem::path& path, const TextureResult& result);

}  // namespace hos::texture
