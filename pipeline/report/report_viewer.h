// The report's 3D view: the textured .glb in @google/model-viewer (vendored
// at build time, see pipeline/CMakeLists.txt). It opens from the first
// registered photo's viewpoint (position, direction and vertical field of
// view, in a frame of the photo's aspect), orbiting a point on that photo's
// optical axis next to the model's centre; the photos' cameras are drawn as
// small frusta, and clicking one moves the view to that photo's. The
// centre and size come from robust bounds of the surface (percentiles of
// its vertices), so stray pieces never set the framing. Script and model
// are embedded in the page: browsers refuse scripts and fetches from
// file:// URLs otherwise.
#pragma once

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/sparse_model.h"
#include "pipeline/stage_paths.h"

namespace hos::pipeline {

// Where the build puts model-viewer's bundle, relative to the executables.
std::filesystem::path default_viewer_script(const std::filesystem::path& bin_dir);

// A photo's view in the viewer's (the glb's scene) coordinates: the root
// matrix applied to the SfM camera, whatever its rotation, translation and
// scale.
struct PhotoView {
  std::string name;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // unit, the optical axis
  double vertical_fov_deg = 45.0;
  double aspect = 4.0 / 3.0;  // width / height
  // The frustum's far corners (top-left, top-right, bottom-right, bottom-left).
  std::array<Eigen::Vector3d, 4> corners;
  // model-viewer's orbit for this view about `target` (on the optical axis):
  // azimuth theta and polar angle phi (radians), radius.
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  double theta = 0.0, phi = 0.0, radius = 1.0;
};

// The model's robust centre and size: the middle of the 2nd-98th percentile
// box of the vertices (in the viewer's coordinates) and its longest side.
struct RobustBounds {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double size = 1.0;
};
std::optional<RobustBounds> robust_bounds(const std::vector<Eigen::Vector3f>& vertices, const Eigen::Matrix4d& root);

// The registered photos' views in image id order (the first registered photo
// first); each orbits the point of its optical axis nearest bounds.centre
// (at least a tenth of the model's size in front of the camera), frusta a
// twentieth of the model's size deep.
std::vector<PhotoView> photo_views(const SparseModel& model, const Eigen::Matrix4d& root, const RobustBounds& bounds);

// The preview hos-texture writes beside the textured model (a decimated
// copy with a small atlas, as texture/model_writer.h's preview_model_path):
// texture/model.preview.glb.
std::filesystem::path report_preview_model(const StagePaths& paths);

// The viewer section; "" when the workspace has no textured model. It
// shows the preview when there is one, else the model itself, and links the
// model; a model too large for the page and without a preview is only
// linked, so that the page stays under 8 MB. Without the script (not built)
// the section is a link to the model.
std::string model_viewer_html(const StagePaths& paths, const std::filesystem::path& viewer_script);

// The whole file ("" if it cannot be read), for data: URIs and the page.
std::string read_bytes(const std::filesystem::path& file);

// Standard base64 (RFC 4648) of bytes, for data: URIs.
std::string base64(const std::string& bytes);

}  // namespace hos::pipeline
