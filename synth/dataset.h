// Rendering a synthetic scene into a dataset with known truth.
//
// Output layout of write_dataset (a contract other stages and tests rely on;
// also in docs/synth.md):
//   DIR/images/view_000.png ...     the photos (.jpg with jpeg)
//   DIR/sparse/{cameras,images,points3D}.txt
//                                   ground-truth COLMAP text model, one PINHOLE
//                                   camera, so DIR is an undistorted workspace
//                                   (core/undistorted_workspace.h). points3D
//                                   holds surface points seen (depth-tested)
//                                   in >= 2 views, with their keypoints.
//   DIR/gt_mesh.ply                 every surface (objects and ground), vertex
//                                   colours = albedo (sRGB)
//   DIR/gt_objects.ply              the objects only
//   DIR/depth/view_000.tiff         CV_32F camera z, 0 = empty (write_depth)
//   DIR/normals/view_000.png        16-bit RGB = world-frame unit normal (x, y, z)
//                                   as round((n + 1) / 2 * 65535), all 0 where
//                                   empty (write_normals; decode_normal_map)
//   DIR/holdout/images, DIR/holdout/sparse
//                                   held-out views, not in DIR/images (holdout > 0)
//   DIR/masks/view_000.png.png      with masked_views: the painted box of the
//                                   first masked_views photos masked out (black)
//   DIR/scene.json                  seed, objects, bounding box, diagonal, up
//                                   axis, light direction, camera tilt, GPS
//                                   origin and metres per unit
// With gps_origin the JPEG views carry their true camera centres as EXIF GPS.
// World up is -y. The folder is written atomically (a temporary folder
// renamed over DIR), so a half-written DIR never looks finished. An existing
// DIR is replaced only if it is empty or holds a scene.json (an earlier
// output); anything else is an OutputError.
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "core/geodesy.h"
#include "core/reporter.h"
#include "core/sparse_model.h"
#include "render/rasterizer.h"
#include "synth/scene.h"

namespace hos::synth {

struct DatasetOptions {
  int num_views = 24;
  int width = 640;
  int height = 480;
  int rings = 2;       // elevation rings the views are spread over
  double focal = 0.0;  // pixels; 0 = 0.9 * width
  bool jpeg = false;
  bool write_depth = false;
  bool write_normals = false;
  int supersampling = 2;
  int holdout = 0;        // extra views for novel-view checks
  int num_points = 3000;  // target size of the sparse ground-truth model
  // Per-view exposure gains (empty = all 1, else num_views entries).
  std::vector<float> exposure_gains;
  // Every camera turned up (positive) or down (negative) by this angle
  // about its x axis after looking at the scene centre, as photos of a
  // facade taken from the street look up; -60..60 degrees.
  double tilt_deg = 0.0;
  // GPS EXIF in the JPEG views (synth/geo_tags.h): the scene origin's
  // position on Earth and the metres of a scene unit.
  std::optional<GeoPosition> gps_origin;
  double metres_per_unit = 1.0;
  // The first masked_views photos get a magenta box painted over part of
  // the scene (a passer-by the geometry does not hold) and a mask that
  // covers it, masks/<image name>.png (core/image_mask.h; the folder to give
  // hos-sfm --masks with images/ as the photos).
  int masked_views = 0;
  void validate() const;  // throws ConfigError
};

struct RenderedDataset {
  SparseModel model;    // cameras, poses, ground-truth sparse points
  SparseModel holdout;  // held-out views (no points)
  std::vector<render::RenderedView> views;
  std::vector<render::RenderedView> holdout_views;
};

// The camera poses: rings around the scene centre, looking at it, objects in frame.
SparseModel make_cameras(const Scene& scene, const DatasetOptions& options);

// The one camera of the views (PINHOLE, focal_of, principal point centred).
Camera dataset_camera(const DatasetOptions& options);

// A view looking at the scene centre from this elevation (above the
// horizon) and azimuth (radians), as close as keeps every object in frame.
ImageRecord view_towards_centre(const Scene& scene, const Camera& camera, double elevation, double azimuth);

RenderedDataset render_dataset(const Scene& scene, const DatasetOptions& options, Reporter& reporter = null_reporter());

// Renders and writes the layout above. Throws OutputError.
void write_dataset(const std::filesystem::path& folder,
                   const Scene& scene,
                   const SceneOptions& scene_options,
                   const DatasetOptions& options,
                   Reporter& reporter = null_reporter());

// 16-bit normal map as written under normals/ and back (CV_32FC3 x, y, z;
// 0 where empty).
cv::Mat encode_normal_map(const cv::Mat& normals);
cv::Mat decode_normal_map(const cv::Mat& encoded);

// The file name of view i ("view_007.png").
std::string view_name(int index, bool jpeg);

}  // namespace hos::synth
