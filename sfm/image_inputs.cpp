#include "sfm/image_inputs.h"

#include <algorithm>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "sfm/exif.h"

namespace hos::sfm {
namespace fs = std::filesystem;
namespace {

constexpr int kMinUsableImages = 3;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

bool is_jpeg_extension(const std::string& ext) { return ext == ".jpg" || ext == ".jpeg"; }

std::string join_skipped(const std::vector<SkippedInput>& skipped) {
  std::string out;
  for (const auto& s : skipped) {
    out += "\n  " + s.file.filename().string() + ": " + s.reason;
  }
  return out;
}

// COLMAP reads only 8 bits per channel; 16-bit PNG and TIFF photos (common
// from raw development) and float TIFFs (taken as 0..1) are scaled down.
cv::Mat to_8_bits(const cv::Mat& image) {
  double scale = 1.0;
  switch (image.depth()) {
    case CV_16U:
      scale = 255.0 / 65535.0;
      break;
    case CV_16S:
      scale = 255.0 / 32767.0;
      break;
    case CV_32F:
    case CV_64F:
      scale = 255.0;
      break;
    default:
      break;
  }
  cv::Mat out;
  image.convertTo(out, CV_8U, scale);
  return out;
}

}  // namespace

const std::vector<std::string>& supported_image_extensions() {
  static const std::vector<std::string> kExtensions{".jpg", ".jpeg", ".png", ".tif", ".tiff", ".bmp"};
  return kExtensions;
}

bool ImageInputs::same_camera() const {
  if (images.empty()) return true;
  const StagedImage& first = images.front();
  return std::all_of(images.begin(), images.end(), [&](const StagedImage& image) {
    return image.width == first.width && image.height == first.height && image.focal_length_mm == first.focal_length_mm;
  });
}

cv::Mat apply_exif_orientation(const cv::Mat& image, int orientation) {
  cv::Mat out;
  switch (orientation) {
    case 2:
      cv::flip(image, out, 1);
      break;  // mirrored horizontally
    case 3:
      cv::flip(image, out, -1);
      break;  // rotated 180
    case 4:
      cv::flip(image, out, 0);
      break;  // mirrored vertically
    case 5:
      cv::transpose(image, out);
      break;
    case 6:  // needs a 90 degree clockwise turn
      cv::transpose(image, out);
      cv::flip(out, out, 1);
      break;
    case 7:
      cv::transpose(image, out);
      cv::flip(out, out, -1);
      break;
    case 8:  // needs a 90 degree counter-clockwise turn
      cv::transpose(image, out);
      cv::flip(out, out, 0);
      break;
    default:
      out = image;
      break;
  }
  return out;
}

namespace {

// The entries at the top level of folder that may be photos, sorted.
std::vector<fs::path> list_photo_candidates(const fs::path& folder) {
  std::error_code ec;
  if (!fs::exists(folder, ec)) throw InputError(folder.string(), "photo folder does not exist");
  if (!fs::is_directory(folder, ec)) throw InputError(folder.string(), "is not a folder of photos");
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || name[0] == '.') continue;
    // An entry that cannot be examined (a symlink loop, a dangling link) is
    // kept here and skipped later with the reason.
    std::error_code entry_ec;
    if (entry.is_directory(entry_ec)) continue;
    files.push_back(entry.path());
  }
  if (ec) throw InputError(folder.string(), "cannot list the folder: " + ec.message());
  std::sort(files.begin(), files.end());
  return files;
}

struct DecodedPhoto {
  cv::Mat image;  // as stored: not yet upright, any bit depth
  ExifInfo exif;
};

// Reads and decodes one file; on failure returns nothing and sets reason.
std::optional<DecodedPhoto> decode_photo(const fs::path& file, const SfmOptions& options, std::string& reason) {
  const std::string ext = lower(file.extension().string());
  const auto& exts = supported_image_extensions();
  if (std::find(exts.begin(), exts.end(), ext) == exts.end()) {
    reason = "not a photo (supported: .jpg .jpeg .png .tif .tiff .bmp)";
    return std::nullopt;
  }
  std::error_code ec;
  const auto size = fs::file_size(file, ec);
  if (ec) {
    reason = "cannot be read: " + ec.message();
    return std::nullopt;
  }
  if (size == 0) {
    reason = "empty file (0 bytes)";
    return std::nullopt;
  }
  std::vector<std::uint8_t> bytes;
  try {
    bytes = read_file_bytes(file);
  } catch (const InputError& e) {
    reason = e.reason();
    return std::nullopt;
  }
  DecodedPhoto photo;
  if (is_jpeg_extension(ext)) {
    if (!jpeg_is_complete(bytes)) {
      reason = "truncated or corrupt JPEG (no complete image data)";
      return std::nullopt;
    }
    photo.exif = parse_jpeg_exif(bytes);
  }
  // Orientation is applied when staging, from our own EXIF reading, so the
  // decoder must not apply it a second time.
  try {
    photo.image = cv::imdecode(bytes, cv::IMREAD_COLOR | cv::IMREAD_ANYDEPTH | cv::IMREAD_IGNORE_ORIENTATION);
  } catch (const cv::Exception&) {
    photo.image.release();
  }
  if (photo.image.empty()) {
    reason = "cannot be decoded as an image (corrupt or unsupported format)";
    return std::nullopt;
  }
  if (std::min(photo.image.cols, photo.image.rows) < options.min_image_size) {
    reason = "too small (" + std::to_string(photo.image.cols) + "x" + std::to_string(photo.image.rows) +
             "; sfm.min_image_size is " + std::to_string(options.min_image_size) + ")";
    return std::nullopt;
  }
  return photo;
}

// The upright photo kThumbnailWidth wide as a small JPEG.
void write_thumbnail(const cv::Mat& image, const fs::path& file) {
  const int height = std::max(1, image.rows * kThumbnailWidth / std::max(image.cols, 1));
  cv::Mat thumbnail;
  cv::resize(image, thumbnail, cv::Size(kThumbnailWidth, height), 0.0, 0.0, cv::INTER_AREA);
  if (!cv::imwrite(file.string(), thumbnail, {cv::IMWRITE_JPEG_QUALITY, 75})) {
    throw OutputError(file.string(), "cannot write the thumbnail");
  }
}

// Puts the photo into staging_dir as COLMAP must see it: 8 bits, upright and
// at most sfm.max_image_size; a link to the user's file when nothing changes.
StagedImage stage_photo(const fs::path& file,
                        DecodedPhoto photo,
                        const fs::path& staging_dir,
                        const fs::path& thumbnail_dir,
                        const SfmOptions& options) {
  StagedImage staged;
  staged.name = file.filename().string();
  staged.source = file;
  staged.focal_length_mm = photo.exif.focal_length_mm;
  staged.gps = photo.exif.gps;
  staged.camera_make = photo.exif.camera_make;
  staged.camera_model = photo.exif.camera_model;
  cv::Mat image = std::move(photo.image);
  if (image.depth() != CV_8U) {
    image = to_8_bits(image);
    staged.rewritten = true;
  }
  if (photo.exif.orientation != 1) {
    image = apply_exif_orientation(image, photo.exif.orientation);
    staged.rewritten = true;
  }
  const int longest = std::max(image.cols, image.rows);
  if (options.max_image_size > 0 && longest > options.max_image_size) {
    const double scale = double(options.max_image_size) / longest;
    cv::Mat small;
    cv::resize(image, small, cv::Size(), scale, scale, cv::INTER_AREA);
    image = small;
    staged.rewritten = true;
  }
  staged.width = image.cols;
  staged.height = image.rows;
  if (!thumbnail_dir.empty()) write_thumbnail(image, thumbnail_dir / (staged.name + ".jpg"));
  const fs::path target = staging_dir / staged.name;
  std::error_code ec;
  fs::remove(target, ec);
  if (staged.rewritten) {
    const std::vector<int> params{cv::IMWRITE_JPEG_QUALITY, 95};
    if (!cv::imwrite(target.string(), image, params)) {
      throw OutputError(target.string(), "cannot write the upright/downscaled copy of " + file.string());
    }
  } else {
    fs::create_symlink(fs::absolute(file), target, ec);
    if (ec) fs::copy_file(file, target, fs::copy_options::overwrite_existing);
  }
  return staged;
}

void require_enough_photos(const fs::path& folder, const ImageInputs& inputs) {
  if (inputs.images.empty() && inputs.skipped.empty()) {
    throw InputError(folder.string(), "contains no photos (supported: .jpg .jpeg .png .tif .tiff .bmp)");
  }
  if (static_cast<int>(inputs.images.size()) < kMinUsableImages) {
    throw InputError(folder.string(),
                     "only " + std::to_string(inputs.images.size()) + " usable photo(s), at least " +
                         std::to_string(kMinUsableImages) + " are needed" +
                         (inputs.skipped.empty() ? std::string() : "; skipped:" + join_skipped(inputs.skipped)));
  }
}

}  // namespace

ImageInputs prepare_images(const fs::path& folder,
                           const fs::path& staging_dir,
                           const SfmOptions& options,
                           Reporter& reporter,
                           const fs::path& thumbnail_dir) {
  const std::vector<fs::path> files = list_photo_candidates(folder);
  ImageInputs inputs;
  fs::create_directories(staging_dir);
  if (!thumbnail_dir.empty()) fs::create_directories(thumbnail_dir);
  reporter.begin("checking photos", static_cast<std::int64_t>(files.size()));
  for (const auto& file : files) {
    reporter.throw_if_cancelled();
    reporter.advance();
    std::string reason;
    std::optional<DecodedPhoto> photo = decode_photo(file, options, reason);
    if (!photo) {
      inputs.skipped.push_back({file, reason});
      reporter.warn("skipping " + file.string() + ": " + reason);
      continue;
    }
    inputs.images.push_back(stage_photo(file, std::move(*photo), staging_dir, thumbnail_dir, options));
  }
  reporter.end();
  require_enough_photos(folder, inputs);
  return inputs;
}

}  // namespace hos::sfm
