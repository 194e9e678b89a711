// Where the model stands when a viewer opens it: the root-node transform of
// the glTF, from the SfM frame to a frame with +Y up, the origin at the
// centre of the model's footprint and at the height of its lowest part (the
// model stands on y = 0), in metres when GPS or a measured distance gives
// the scale.
//
// The vertical comes from texture/up_direction.h, or from the GPS fit when
// it fixes the tilt well (texture/geo_alignment.h). Horizontally, with GPS
// +X is east and -Z north; otherwise the cameras' mean viewing direction
// becomes -Z (so a viewer looking along -Z sees the side the photos saw).
// Footprint and base use robust extents of the vertices (1st-99th percentile
// horizontally, the 0.5th percentile of height), so stray pieces do not move
// them. Vertices stay in the SfM frame; apply_root_matrix bakes the
// transform into them for formats without a node hierarchy.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/geodesy.h"
#include "texture/geo_alignment.h"
#include "texture/textured_mesh.h"
#include "texture/up_direction.h"

namespace hos::texture {

// Two photos' camera centres measured on site (hos-pipeline --scale-distance).
struct ScaleDistance {
  std::string photo_a, photo_b;
  double metres = 0.0;
};

// "A.jpg B.jpg METRES" (texture.scale_distance): throws ConfigError naming
// that key unless it is two names without spaces and a positive number.
ScaleDistance parse_scale_distance(const std::string& text);

// What placement knows beyond the cameras and the surface.
struct PlacementInput {
  std::vector<PhotoPosition> photo_positions;   // GPS of the photos (empty: none)
  std::optional<ScaleDistance> scale_distance;  // takes precedence over GPS
};

struct PlacementOptions {
  UpOptions up;
  GeoAlignmentOptions gps;
  double footprint_percentile = 0.01;  // horizontal extents: this to 1 - this
  double base_percentile = 0.005;      // height the model stands at
};

struct Placement {
  Eigen::Matrix4d root_matrix = Eigen::Matrix4d::Identity();  // SfM frame -> placed frame
  UpEstimate up;                                              // in the SfM frame
  double scale = 1.0;                                         // placed units per SfM unit
  bool metric = false;                                        // placed units are metres
  std::string units;                // "metres from GPS", "metres from the measured distance" or "arbitrary (COLMAP's)"
  std::string units_reason;         // why arbitrary, e.g. "no GPS" or "GPS spread 8 m < 20 m"
  std::optional<GeoAlignment> gps;  // the GPS fit, when there was GPS to try
  std::optional<GeoPosition> geo_origin;  // the placed origin on Earth (GPS placement only)
  // One line for reports: "units: metres from GPS (12 photos, residual 2.1 m)",
  // "units: arbitrary (COLMAP's), because: no GPS".
  std::string units_text() const;
};

// Throws ConfigError (key "texture.scale_distance") when a photo of
// input.scale_distance is not among the cameras, the two are the same
// photo or their centres coincide.
Placement place_model(const std::vector<Eigen::Vector3f>& vertices,
                      const std::vector<CameraPose>& cameras,
                      const PlacementInput& input = {},
                      const PlacementOptions& options = {});

// The placement's transform applied to the vertices (positions, normals)
// of the mesh; its root matrix becomes the identity.
void apply_root_matrix(TexturedMesh& mesh);

}  // namespace hos::texture
