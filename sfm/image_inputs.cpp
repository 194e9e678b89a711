#include "sfm/image_inputs.h"

#include <algorithm>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>

#include "core/error.h"
#include "core/image_mask.h"
#include "core/jpeg_encoding.h"
#include "core/text.h"
#include "sfm/exif.h"
#include "sfm/heif_decoder.h"
#include "sfm/photo_format.h"
#include "sfm/photo_masks.h"

namespace hos::sfm {
namespace fs = std::filesystem;
namespace {

constexpr int kMinUsableImages = 3;
constexpr const char* kReadFormats = "JPEG, PNG, TIFF, BMP or HEIC/HEIF";
// JPEG quality of the copies hos re-encodes (turned, shrunk, HEIC): 100,
// whose unit quantisation keeps the pixels within rounding (a 6 MP copy
// takes 4.5 MB against 1.8 MB at 95). At 95 the copies of turned photos
// moved SIFT's keypoints enough to raise the SfM rotation errors of a dark
// synthetic capture from 0.063 to 0.077 degrees (0.068 at 100).
constexpr int kCopyJpegQuality = 100;

std::string join_skipped(const std::vector<SkippedInput>& skipped) {
  std::string out;
  for (const auto& s : skipped) {
    out += "\n  " + s.file.string() + ": " + s.reason;
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

bool is_hidden(const fs::path& path) {
  const std::string name = path.filename().string();
  return !name.empty() && name[0] == '.';
}

// The excluded folders as the search meets them (resolved), so that
// "photos/ws", "./photos/ws/" and a link to it all match.
std::vector<fs::path> resolved(const std::vector<fs::path>& folders) {
  std::vector<fs::path> out;
  for (const fs::path& folder : folders) {
    std::error_code ec;
    const fs::path p = fs::weakly_canonical(fs::absolute(folder, ec), ec);
    if (!ec && !p.empty()) out.push_back(p.lexically_normal());
  }
  return out;
}

bool is_excluded_folder(const fs::path& folder, const std::vector<fs::path>& excluded) {
  if (is_hidden(folder) || is_hos_workspace(folder)) return true;
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(folder, ec).lexically_normal();
  return !ec && std::find(excluded.begin(), excluded.end(), p) != excluded.end();
}

}  // namespace

int ImageInputs::masked_photos() const {
  return static_cast<int>(std::count_if(images.begin(), images.end(), [](const StagedImage& i) { return i.masked; }));
}

bool ImageInputs::same_camera() const {
  if (images.empty()) return true;
  const StagedImage& first = images.front();
  return std::all_of(images.begin(), images.end(), [&](const StagedImage& image) {
    return image.width == first.width && image.height == first.height &&
           image.focal_length_mm == first.focal_length_mm && image.video_clip == first.video_clip;
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

bool is_hos_workspace(const fs::path& folder) {
  std::error_code ec;
  return fs::exists(folder / "run.json", ec) || fs::exists(folder / "sfm" / "report.json", ec) ||
         fs::exists(folder / "sfm" / "database.db", ec);
}

std::vector<fs::path> list_input_files(const fs::path& folder, const std::vector<fs::path>& excluded) {
  const std::vector<fs::path> excluded_folders = resolved(excluded);
  std::vector<fs::path> files;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(folder, fs::directory_options::skip_permission_denied, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    std::error_code entry_ec;
    const bool is_folder = it->is_directory(entry_ec);
    if (is_folder && (it->is_symlink(entry_ec) || is_excluded_folder(it->path(), excluded_folders))) {
      it.disable_recursion_pending();
      continue;
    }
    // An entry that cannot be examined (a symlink loop, a dangling link) is
    // kept here and skipped later with the reason.
    if (is_folder || is_hidden(it->path())) continue;
    files.push_back(it->path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<fs::path> list_photo_files(const fs::path& folder, const std::vector<fs::path>& excluded) {
  std::error_code ec;
  if (fs::is_regular_file(folder, ec)) return {folder};  // a single video clip
  std::vector<fs::path> photos;
  for (const fs::path& file : list_input_files(folder, excluded)) {
    if (photo_format_of_file(file) != PhotoFormat::kUnknown || is_video_file(file)) photos.push_back(file);
  }
  return photos;
}

namespace {

void require_photo_folder(const fs::path& folder) {
  std::error_code ec;
  if (!fs::exists(folder, ec)) throw InputError(folder.string(), "photo folder does not exist");
  if (!fs::is_directory(folder, ec)) throw InputError(folder.string(), "is not a folder of photos");
  fs::directory_iterator probe(folder, ec);
  if (ec) throw InputError(folder.string(), "cannot list the folder: " + ec.message());
}

struct DecodedPhoto {
  PhotoFormat format = PhotoFormat::kUnknown;
  cv::Mat image;        // not yet upright (but for HEIF), any bit depth
  ExifBlock exif;       // the whole block, for the staged copy
  ExifInfo info;        // what the stage uses of it
  int orientation = 1;  // the turn still to apply (HEIF: already applied by the decoder)
  cv::Mat alpha_mask;   // of a photo transparent in places (sfm/photo_masks.h's mask_from_alpha), else empty
};

// A PNG or TIFF decoded as stored: its colour as three channels, its alpha
// channel, if any, as photo.alpha_mask. False for another channel count.
bool split_alpha(cv::Mat decoded, DecodedPhoto& photo) {
  if (decoded.channels() == 4) {
    cv::Mat alpha;
    cv::extractChannel(decoded, alpha, 3);
    photo.alpha_mask = mask_from_alpha(alpha);
    cv::cvtColor(decoded, photo.image, cv::COLOR_BGRA2BGR);
  } else if (decoded.channels() == 1) {
    cv::cvtColor(decoded, photo.image, cv::COLOR_GRAY2BGR);
  } else if (decoded.channels() == 3) {
    photo.image = std::move(decoded);
  } else {
    return false;
  }
  return true;
}

// Decodes bytes of a format OpenCV reads (JPEG, PNG, TIFF, BMP).
bool decode_with_opencv(const std::vector<std::uint8_t>& bytes, DecodedPhoto& photo) {
  // Orientation is applied when staging, from our own EXIF reading, so the
  // decoder must not apply it a second time. PNG and TIFF may carry an
  // alpha channel (a renderer's transparent background).
  const bool may_have_alpha = photo.format == PhotoFormat::kPng || photo.format == PhotoFormat::kTiff;
  try {
    if (!may_have_alpha ||
        !split_alpha(cv::imdecode(bytes, cv::IMREAD_UNCHANGED | cv::IMREAD_IGNORE_ORIENTATION), photo)) {
      photo.image = cv::imdecode(bytes, cv::IMREAD_COLOR | cv::IMREAD_ANYDEPTH | cv::IMREAD_IGNORE_ORIENTATION);
    }
  } catch (const cv::Exception&) {
    photo.image.release();
  }
  photo.exif = read_exif(bytes);
  photo.info = photo.exif.info();
  photo.orientation = photo.info.orientation;
  return !photo.image.empty();
}

bool decode_heif_photo(const std::vector<std::uint8_t>& bytes, DecodedPhoto& photo, std::string& reason) {
  std::optional<HeifPhoto> heif = decode_heif(bytes, reason);
  if (!heif) return false;
  photo.image = std::move(heif->image);
  photo.exif = std::move(heif->exif);
  photo.info = photo.exif.info();
  photo.orientation = 1;  // libheif turned it already
  return true;
}

// Reads and decodes one file by its content; on failure returns nothing and
// sets reason.
std::optional<DecodedPhoto> decode_photo(const fs::path& file, const SfmOptions& options, std::string& reason) {
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
  photo.format = photo_format_of(bytes.data(), bytes.size());
  switch (photo.format) {
    case PhotoFormat::kUnknown:
      reason = std::string("not a photo (its content is not ") + kReadFormats + ")";
      return std::nullopt;
    case PhotoFormat::kHeif:
      if (!decode_heif_photo(bytes, photo, reason)) return std::nullopt;
      break;
    case PhotoFormat::kJpeg:
      if (!jpeg_is_complete(bytes)) {
        reason = "truncated or corrupt JPEG (no complete image data)";
        return std::nullopt;
      }
      [[fallthrough]];
    default:
      if (!decode_with_opencv(bytes, photo)) {
        reason = "cannot be decoded as an image (corrupt " + photo_format_name(photo.format) + ")";
        return std::nullopt;
      }
  }
  if (std::min(photo.image.cols, photo.image.rows) < options.min_image_size) {
    reason = "too small (" + std::to_string(photo.image.cols) + "x" + std::to_string(photo.image.rows) +
             "; sfm.min_image_size is " + std::to_string(options.min_image_size) + ")";
    return std::nullopt;
  }
  return photo;
}

// The staged name: the path relative to the photo folder; a HEIC becomes a
// JPEG (COLMAP cannot read HEIC), so its name says so.
std::string staged_name(const std::string& relative, PhotoFormat format) {
  if (format != PhotoFormat::kHeif) return relative;
  const std::string ext = lower_case_extension(relative);
  return ext == ".jpg" || ext == ".jpeg" ? relative : relative + ".jpg";
}

// The encoding of a re-encoded copy: the photo's own (JPEG stays JPEG, PNG
// and TIFF stay lossless), but JPEG for a HEIC, which COLMAP cannot read.
std::string copy_encoding(PhotoFormat format) {
  switch (format) {
    case PhotoFormat::kPng:
      return ".png";
    case PhotoFormat::kTiff:
      return ".tif";
    case PhotoFormat::kBmp:
      return ".bmp";
    default:
      return ".jpg";
  }
}

void write_encoded(const cv::Mat& image, PhotoFormat format, const fs::path& target, const fs::path& source) {
  const std::string encoding = copy_encoding(format);
  const std::string what = "the upright/downscaled copy of " + source.string();
  // Full chroma: OpenCV's 4:2:0 would blur the colour edges mvs and texture
  // use (about 1 dB of the copy's PSNR at quality 95).
  if (encoding == ".jpg") return write_jpeg_444(image, kCopyJpegQuality, target, what);
  std::vector<std::uint8_t> bytes;
  std::ofstream out;
  if (cv::imencode(encoding, image, bytes)) {
    out.open(target, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  }
  if (!out) throw OutputError(target.string(), what);
}

// Puts the photo into staging_dir as COLMAP must see it: 8 bits, upright,
// at most sfm.max_image_size, JPEG rather than HEIC, with the photo's EXIF
// (and a GPS altitude when it has a position without one); a link to the
// user's file when nothing changes.
StagedImage stage_photo(const fs::path& file,
                        const std::string& name,
                        DecodedPhoto photo,
                        const std::optional<fs::path>& mask,
                        const fs::path& staging_dir,
                        const fs::path& thumbnail_dir,
                        const SfmOptions& options,
                        Reporter& reporter) {
  StagedImage staged;
  PhotoTransform transform{photo.image.cols, photo.image.rows, photo.orientation, 0, 0};
  staged.name = name;
  staged.source = file;
  staged.focal_length_mm = photo.info.focal_length_mm;
  staged.gps = photo.info.gps;
  staged.gps_altitude_missing = staged.gps && !staged.gps->altitude_m;
  staged.camera_make = photo.info.camera_make;
  staged.camera_model = photo.info.camera_model;
  cv::Mat image = std::move(photo.image);
  StagedCopyChanges changes;
  // A photo with transparent pixels is staged without its alpha channel, which
  // COLMAP would read in different ways; its mask says what is transparent.
  staged.rewritten = photo.format == PhotoFormat::kHeif || !photo.alpha_mask.empty();
  if (image.depth() != CV_8U) {
    image = to_8_bits(image);
    staged.rewritten = true;
  }
  if (photo.orientation != 1) {
    image = apply_exif_orientation(image, photo.orientation);
    changes.transposed = photo.orientation >= 5;
    staged.rewritten = true;
  }
  const int longest = std::max(image.cols, image.rows);
  if (options.max_image_size > 0 && longest > options.max_image_size) {
    changes.scale = double(options.max_image_size) / longest;
    cv::Mat small;
    cv::resize(image, small, cv::Size(), changes.scale, changes.scale, cv::INTER_AREA);
    image = small;
    staged.rewritten = true;
  }
  staged.width = changes.width = transform.staged_width = image.cols;
  staged.height = changes.height = transform.staged_height = image.rows;
  if (mask) {
    // Checked before anything is written: a bad mask fails the stage.
    write_mask(stage_mask(*mask, file, transform), mask_file(staged_mask_folder(staging_dir), staged.name));
    staged.masked = true;
  } else if (!photo.alpha_mask.empty()) {
    write_mask(transform_mask(photo.alpha_mask, transform), mask_file(staged_mask_folder(staging_dir), staged.name));
    staged.masked = staged.masked_by_alpha = true;
  }
  changes.write_zero_altitude = staged.gps_altitude_missing;
  if (!thumbnail_dir.empty()) {
    const fs::path thumbnail = thumbnail_dir / (staged.name + ".jpg");
    fs::create_directories(thumbnail.parent_path());
    write_thumbnail(image, thumbnail);
  }
  const fs::path target = staging_dir / staged.name;
  fs::create_directories(target.parent_path());
  std::error_code ec;
  fs::remove(target, ec);
  const bool copy_exif = staged.rewritten || changes.write_zero_altitude;
  if (staged.rewritten) {
    write_encoded(image, photo.format, target, file);
  } else if (copy_exif) {
    fs::copy_file(file, target, fs::copy_options::overwrite_existing);  // bytes as they are; EXIF below
  } else {
    fs::create_symlink(fs::absolute(file), target, ec);
    if (ec) fs::copy_file(file, target, fs::copy_options::overwrite_existing);
  }
  if (copy_exif) {
    try {
      write_staged_exif(photo.exif, changes, target);
    } catch (const OutputError& e) {
      // The pixels are fine; COLMAP then only lacks the focal length prior.
      reporter.warn(std::string(e.what()) + " (staged without EXIF)");
    }
  }
  return staged;
}

void require_enough_photos(const fs::path& folder, const ImageInputs& inputs) {
  if (inputs.images.empty() && inputs.skipped.empty()) {
    throw InputError(folder.string(), std::string("contains no photos (searched with its subfolders; ") + kReadFormats +
                                          " files are read, by content)");
  }
  if (static_cast<int>(inputs.images.size()) < kMinUsableImages) {
    throw InputError(folder.string(),
                     "only " + std::to_string(inputs.images.size()) + " usable photo(s), at least " +
                         std::to_string(kMinUsableImages) + " are needed" +
                         (inputs.skipped.empty() ? std::string() : "; skipped:" + join_skipped(inputs.skipped)));
  }
}

void require_mask_folder(const fs::path& mask_folder) {
  std::error_code ec;
  if (mask_folder.empty() || fs::is_directory(mask_folder, ec)) return;
  throw InputError(mask_folder.string(), fs::exists(mask_folder, ec) ? "sfm.masks is not a folder"
                                                                     : "mask folder (sfm.masks) does not exist");
}

// Says how many photos have masks, and names the masks of the folder that
// belong to no photo (a misspelt name would leave its photo unmasked).
void report_masks(const fs::path& mask_folder,
                  int masks_beside,
                  const std::set<std::string>& photo_names,
                  Reporter& reporter,
                  const ImageInputs& inputs) {
  const int by_alpha = static_cast<int>(std::count_if(inputs.images.begin(), inputs.images.end(),
                                                      [](const StagedImage& i) { return i.masked_by_alpha; }));
  const int masked = inputs.masked_photos() - by_alpha;  // by a mask file
  const int photos = static_cast<int>(std::count_if(inputs.images.begin(), inputs.images.end(),
                                                    [](const StagedImage& i) { return i.video_clip.empty(); }));
  if (by_alpha > 0) {
    reporter.info(format_message("masks: ", by_alpha, " of ", photos,
                                 " photos are transparent in places; their alpha channel masks those pixels "
                                 "(no features, depths or texture there)"));
  }
  if (!mask_folder.empty()) {
    reporter.info(format_message("masks: ", masked, " of ", photos, " photos have a mask in ", mask_folder.string(),
                                 masked + by_alpha < photos ? " (the others are used whole)" : ""));
    if (masks_beside > 0) {
      reporter.warn(format_message("masks: ", masks_beside,
                                   " PHOTO.png file(s) beside the photos are ignored: "
                                   "sfm.masks names the mask folder"));
    }
    std::vector<std::string> unmatched;
    for (const fs::path& file : list_input_files(mask_folder)) {
      const std::string relative = file.lexically_relative(mask_folder).generic_string();
      const bool fits = relative.size() > 4 && relative.ends_with(".png") &&
                        photo_names.count(relative.substr(0, relative.size() - 4)) > 0;
      if (!fits) unmatched.push_back(relative);
    }
    if (!unmatched.empty()) {
      reporter.warn(format_message("masks: ", unmatched.size(), " file(s) in ", mask_folder.string(),
                                   " belong to no photo (a photo NAME's mask is NAME.png), e.g. ", unmatched.front()));
    }
  } else if (masked > 0) {
    reporter.info(format_message("masks: ", masked, " of ", photos, " photos have a mask (PHOTO.png beside PHOTO)"));
  }
}

void skip(const fs::path& file, const std::string& reason, Reporter& reporter, ImageInputs& inputs) {
  inputs.skipped.push_back({file, reason});
  reporter.warn("skipping " + file.string() + ": " + reason);
}

}  // namespace

// The upright photo kThumbnailWidth wide as a small JPEG.
void write_thumbnail(const cv::Mat& image, const fs::path& file) {
  const int height = std::max(1, image.rows * kThumbnailWidth / std::max(image.cols, 1));
  cv::Mat thumbnail;
  cv::resize(image, thumbnail, cv::Size(kThumbnailWidth, height), 0.0, 0.0, cv::INTER_AREA);
  if (!cv::imwrite(file.string(), thumbnail, {cv::IMWRITE_JPEG_QUALITY, 75})) {
    throw OutputError(file.string(), "the thumbnail");
  }
}

ImageInputs prepare_images(const fs::path& folder,
                           const fs::path& staging_dir,
                           const SfmOptions& options,
                           Reporter& reporter,
                           const fs::path& thumbnail_dir,
                           const std::vector<fs::path>& excluded) {
  // A single video clip stands for a folder holding only it.
  const bool single_clip = is_video_file(folder);
  if (!single_clip) require_photo_folder(folder);
  const fs::path mask_folder = options.mask_folder();
  require_mask_folder(mask_folder);
  std::vector<fs::path> excluded_here = excluded;
  excluded_here.push_back(staging_dir);
  excluded_here.push_back(staged_mask_folder(staging_dir));
  if (!mask_folder.empty()) excluded_here.push_back(mask_folder);
  if (!thumbnail_dir.empty()) excluded_here.push_back(thumbnail_dir);
  const std::vector<fs::path> files =
      single_clip ? std::vector<fs::path>{folder} : list_input_files(folder, excluded_here);
  const std::set<fs::path> listed(files.begin(), files.end());
  ImageInputs inputs;
  fs::create_directories(staging_dir);
  if (!thumbnail_dir.empty()) fs::create_directories(thumbnail_dir);
  std::set<std::string> staged_names;
  std::set<std::string> photo_names;  // relative paths, for the masks that fit no photo
  int masks_beside = 0;
  reporter.begin("checking photos", static_cast<std::int64_t>(files.size()));
  for (const auto& file : files) {
    reporter.throw_if_cancelled();
    reporter.advance();
    const std::string relative =
        single_clip ? file.filename().string() : file.lexically_relative(folder).generic_string();
    if (is_video_file(file)) {
      stage_video(file, relative, staging_dir, thumbnail_dir, options, reporter, inputs);
      continue;
    }
    if (!single_clip && is_mask_beside_photo(file, listed)) {
      ++masks_beside;  // PHOTO.png beside PHOTO: its mask, not a photo
      continue;
    }
    std::string reason;
    std::optional<DecodedPhoto> photo = decode_photo(file, options, reason);
    if (!photo) {
      skip(file, reason, reporter, inputs);
      continue;
    }
    const std::string name = staged_name(relative, photo->format);
    if (!staged_names.insert(name).second) {
      skip(file, "its staged name " + name + " is taken by another photo", reporter, inputs);
      continue;
    }
    photo_names.insert(relative);
    const std::optional<fs::path> mask = find_mask(mask_folder, folder, relative);
    inputs.images.push_back(
        stage_photo(file, name, std::move(*photo), mask, staging_dir, thumbnail_dir, options, reporter));
  }
  reporter.end();
  report_masks(mask_folder, masks_beside, photo_names, reporter, inputs);
  if (inputs.masked_photos() > 0) inputs.mask_folder = staged_mask_folder(staging_dir);
  std::sort(inputs.images.begin(), inputs.images.end(),
            [](const StagedImage& a, const StagedImage& b) { return a.name < b.name; });
  require_enough_photos(folder, inputs);
  return inputs;
}

}  // namespace hos::sfm
