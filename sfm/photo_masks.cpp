#include "sfm/photo_masks.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/image_mask.h"
#include "core/reporter.h"
#include "sfm/image_inputs.h"

namespace hos::sfm {
namespace fs = std::filesystem;

fs::path staged_mask_folder(const fs::path& staging_dir) {
  const fs::path dir = staging_dir.has_filename() ? staging_dir : staging_dir.parent_path();
  return dir.parent_path() / "masks";
}

bool is_mask_beside_photo(const fs::path& file, const std::set<fs::path>& files) {
  if (file.extension() != ".png") return false;
  fs::path photo = file;
  photo.replace_extension();
  return photo.has_extension() && files.count(photo) > 0;
}

std::optional<fs::path> find_mask(const fs::path& mask_folder,
                                  const fs::path& photo_folder,
                                  const std::string& relative) {
  const fs::path file = mask_file(mask_folder.empty() ? photo_folder : mask_folder, relative);
  std::error_code ec;
  if (!fs::exists(file, ec)) return std::nullopt;
  return file;
}

cv::Mat stage_mask(const fs::path& mask_path, const fs::path& photo, const PhotoTransform& t) {
  cv::Mat mask = read_mask(mask_path);
  const bool stored = mask.cols == t.stored_width && mask.rows == t.stored_height;
  const bool quarter_turn = t.orientation >= 5;
  const bool upright = quarter_turn && mask.cols == t.stored_height && mask.rows == t.stored_width;
  if (!stored && !upright) {
    throw InputError(mask_path.string(), format_message("mask is ", mask.cols, "x", mask.rows, " pixels but its photo ",
                                                        photo.string(), " is ", t.stored_width, "x", t.stored_height,
                                                        quarter_turn ? format_message(" (", t.stored_height, "x",
                                                                                      t.stored_width, " upright)")
                                                                     : std::string()));
  }
  PhotoTransform as_drawn = t;
  if (!stored) as_drawn.orientation = 1;  // drawn upright: no turn left to apply
  return transform_mask(mask, as_drawn);
}

cv::Mat mask_from_alpha(const cv::Mat& alpha) {
  double half_opaque = 128.0;
  if (alpha.depth() == CV_16U) half_opaque = 32768.0;
  if (alpha.depth() == CV_32F || alpha.depth() == CV_64F) half_opaque = 0.5;
  static_assert(kUsable == 255 && kMaskedOut == 0, "the comparison's values are the mask's");
  cv::Mat mask = alpha >= half_opaque;
  if (cv::countNonZero(mask) == static_cast<int>(mask.total())) return {};
  return mask;
}

cv::Mat transform_mask(cv::Mat mask, const PhotoTransform& t) {
  mask = apply_exif_orientation(mask, t.orientation);
  if (mask.cols != t.staged_width || mask.rows != t.staged_height) {
    cv::Mat small;
    cv::resize(mask, small, cv::Size(t.staged_width, t.staged_height), 0.0, 0.0, cv::INTER_NEAREST);
    mask = small;
  }
  return mask;
}

namespace {

// The distorted pixel each undistorted pixel's ray meets, nearest, as
// COLMAP's WarpImageBetweenCameras looks it up (pixel centres at +0.5).
cv::Mat warp_mask(const cv::Mat& mask, const Camera& distorted, const Camera& pinhole) {
  cv::Mat out(pinhole.height, pinhole.width, CV_8U, cv::Scalar(kMaskedOut));
  for (int y = 0; y < pinhole.height; ++y) {
    auto* row = out.ptr<unsigned char>(y);
    for (int x = 0; x < pinhole.width; ++x) {
      const Eigen::Vector3d ray((x + 0.5 - pinhole.principal_x()) / pinhole.focal_x(),
                                (y + 0.5 - pinhole.principal_y()) / pinhole.focal_y(), 1.0);
      const std::optional<Eigen::Vector2d> p = distorted.project(ray);
      if (!p || !std::isfinite(p->x()) || !std::isfinite(p->y())) continue;
      const double sx = std::floor(p->x()), sy = std::floor(p->y());
      if (sx < 0 || sy < 0 || sx >= mask.cols || sy >= mask.rows) continue;
      row[x] = mask.at<unsigned char>(static_cast<int>(sy), static_cast<int>(sx));
    }
  }
  return out;
}

}  // namespace

int undistort_masks(const SparseModel& distorted,
                    const SparseModel& undistorted,
                    const fs::path& masks,
                    const fs::path& out_folder) {
  int written = 0;
  for (const auto& [id, image] : undistorted.images) {
    const ImageRecord* source = distorted.find_image(image.name);
    if (source == nullptr) continue;
    const fs::path file = mask_file(masks, image.name);
    std::error_code ec;
    if (!fs::exists(file, ec)) continue;
    const Camera& camera = distorted.camera_of(*source);
    const cv::Mat mask = read_mask(file, camera.width, camera.height, image.name);
    write_mask(warp_mask(mask, camera, undistorted.camera_of(image)), mask_file(out_folder, image.name));
    ++written;
  }
  return written;
}

}  // namespace hos::sfm
