// Analytic test scenes for the texture tests: a sphere with a smooth
// procedural albedo, photographed by ray casting the exact sphere (not the
// mesh under test), unlit, so the true colour of every surface point is known.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <optional>
#include <vector>

#include "core/types.h"
#include "texture/mesh_topology.h"
#include "texture/texture_view.h"
#include "texture/textured_mesh.h"

namespace hos::texture::testing {

// Albedo in [0, 1] RGB: smooth stripes, never strongly red.
Eigen::Vector3f sphere_albedo(const Eigen::Vector3f& x);

// A camera at distance from the origin, looking at it, at the given azimuth
// and elevation (degrees); world up is +z.
// "v<i>": the name of the i-th test view.
std::string view_name(int i);

TextureView make_view(const std::string& name,
                      double azimuth_deg,
                      double elevation_deg,
                      double distance,
                      int width = 320,
                      int height = 240,
                      double focal = 300.0);

// An undistorted workspace on disk (images/ and a text sparse/ model with
// one PINHOLE camera): num_views photos of the unit sphere (render_sphere),
// 320x240, around it at distance 3.5, alternately 30 degrees above and below.
void write_sphere_workspace(const std::filesystem::path& folder, int num_views);

struct Occluder {
  Eigen::Vector3d center;
  double radius = 0.1;
  Eigen::Vector3f rgb = Eigen::Vector3f(1.0f, 0.0f, 0.0f);
};

// Ray-casts the sphere (radius at the origin) into view.image; colour =
// albedo * gain (8 bit), black background; an optional occluder in front.
void render_sphere(TextureView& view,
                   double radius,
                   float gain = 1.0f,
                   const std::optional<Occluder>& occluder = std::nullopt);

// Bilinear sample of an atlas (BGR) at glTF UV; returns RGB in [0, 255].
Eigen::Vector3f sample_atlas(const cv::Mat& atlas, const Eigen::Vector2f& uv);

// A sample point of the textured result: page, UV, and 3D position.
struct TexturePoint {
  int page = 0;
  Eigen::Vector2f uv;
  Eigen::Vector3f position;
  bool flat = false;  // the triangle's UVs are all equal (unseen-face patch)
};
// Points at the centroid and three inner points of every triangle.
std::vector<TexturePoint> texture_points(const TexturedMesh& mesh);

// Renders a textured mesh (perspective-correct UVs, bilinear atlas lookup,
// z-buffer, unlit) into a BGR image of the view's size; mask is 255 where the
// mesh covers the pixel centre. Test-only stand-in for a glTF viewer.
void render_textured(const TexturedMesh& mesh, const TextureView& view, cv::Mat& image, cv::Mat& mask);

// Six photos of the unit sphere (render_sphere), from make_view at 60-degree
// steps of azimuth, elevation_deg up, at distance 3.5.
std::vector<TextureView> six_views_of_sphere(double elevation_deg);

// The unit icosphere (subdivision 3) textured from six_views_of_sphere(10).
TexturedMesh textured_sphere(int atlas_size = 4096);

// A strip of n faces, face i adjacent to i-1 and i+1.
MeshTopology strip_topology(int n);

}  // namespace hos::texture::testing
