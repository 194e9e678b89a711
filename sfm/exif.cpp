#include "sfm/exif.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>

// exiv2 0.27 names std::auto_ptr in its API (Image::AutoPtr).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#include <exiv2/exiv2.hpp>

#include "core/error.h"

namespace hos::sfm {
namespace {

// exiv2 logs every oddity of a photo's metadata to stderr; the stage decides
// what the user sees.
void quiet_exiv2() {
  static const bool muted = [] {
    Exiv2::LogMsg::setLevel(Exiv2::LogMsg::mute);
    return true;
  }();
  (void)muted;
}

const Exiv2::Exifdatum* find(const Exiv2::ExifData& exif, const char* key) {
  const auto it = exif.findKey(Exiv2::ExifKey(key));
  return it == exif.end() ? nullptr : &*it;
}

// One rational component of a tag as a double; nothing for a zero
// denominator or a missing component.
std::optional<double> rational(const Exiv2::Exifdatum* datum, long n = 0) {
  if (datum == nullptr || datum->count() <= n) return std::nullopt;
  const Exiv2::TypeId type = datum->typeId();
  if (type != Exiv2::unsignedRational && type != Exiv2::signedRational) return std::nullopt;
  const Exiv2::Rational r = datum->toRational(n);
  if (r.second == 0) return std::nullopt;
  const double value = double(r.first) / double(r.second);
  return std::isfinite(value) ? std::optional<double>(value) : std::nullopt;
}

std::string trimmed_text(const Exiv2::Exifdatum* datum) {
  if (datum == nullptr) return {};
  std::string s = datum->toString();
  const auto keep = [](unsigned char c) { return c != 0 && !std::isspace(c); };
  s.erase(std::find_if(s.rbegin(), s.rend(), keep).base(), s.end());
  s.erase(s.begin(), std::find_if(s.begin(), s.end(), keep));
  return s;
}

// Degrees, minutes, seconds (three rationals) signed by the reference
// letter ("S" or "W" negative).
std::optional<double> gps_coordinate(
    const Exiv2::ExifData& exif, const char* key, const char* ref_key, char negative, double limit) {
  const Exiv2::Exifdatum* datum = find(exif, key);
  const auto degrees = rational(datum, 0), minutes = rational(datum, 1), seconds = rational(datum, 2);
  if (!degrees || !minutes || !seconds) return std::nullopt;
  double value = *degrees + *minutes / 60.0 + *seconds / 3600.0;
  if (!(value >= 0.0 && value <= limit)) return std::nullopt;
  const std::string ref = trimmed_text(find(exif, ref_key));
  if (!ref.empty() && std::toupper(static_cast<unsigned char>(ref[0])) == negative) value = -value;
  return value;
}

std::optional<GpsPosition> gps_position(const Exiv2::ExifData& exif) {
  const auto latitude = gps_coordinate(exif, "Exif.GPSInfo.GPSLatitude", "Exif.GPSInfo.GPSLatitudeRef", 'S', 90.0);
  const auto longitude = gps_coordinate(exif, "Exif.GPSInfo.GPSLongitude", "Exif.GPSInfo.GPSLongitudeRef", 'W', 180.0);
  if (!latitude || !longitude) return std::nullopt;
  GpsPosition gps;
  gps.latitude_deg = *latitude;
  gps.longitude_deg = *longitude;
  gps.altitude_m = rational(find(exif, "Exif.GPSInfo.GPSAltitude"));
  // AltitudeRef 1: below sea level.
  const Exiv2::Exifdatum* ref = find(exif, "Exif.GPSInfo.GPSAltitudeRef");
  if (gps.altitude_m && ref != nullptr && ref->count() > 0 && ref->toLong(0) == 1) gps.altitude_m = -*gps.altitude_m;
  return gps;
}

// Tags that describe a TIFF file's own pixel data, not the photo: a staged
// copy has its own, written by its encoder.
constexpr const char* kImageStructureTags[] = {"Exif.Image.ImageWidth",
                                               "Exif.Image.ImageLength",
                                               "Exif.Image.BitsPerSample",
                                               "Exif.Image.Compression",
                                               "Exif.Image.PhotometricInterpretation",
                                               "Exif.Image.StripOffsets",
                                               "Exif.Image.SamplesPerPixel",
                                               "Exif.Image.RowsPerStrip",
                                               "Exif.Image.StripByteCounts",
                                               "Exif.Image.PlanarConfiguration",
                                               "Exif.Image.TileWidth",
                                               "Exif.Image.TileLength",
                                               "Exif.Image.TileOffsets",
                                               "Exif.Image.TileByteCounts",
                                               "Exif.Image.SampleFormat",
                                               "Exif.Image.ExtraSamples",
                                               "Exif.Image.Predictor",
                                               "Exif.Image.NewSubfileType",
                                               "Exif.Image.SubIFDs",
                                               "Exif.Image.JPEGInterchangeFormat",
                                               "Exif.Image.JPEGInterchangeFormatLength"};

void erase_key(Exiv2::ExifData& exif, const char* key) {
  const auto it = exif.findKey(Exiv2::ExifKey(key));
  if (it != exif.end()) exif.erase(it);
}

Exiv2::URational to_urational(double value) {
  const double clamped = std::clamp(value, 0.0, 4.0e6);
  return {static_cast<std::uint32_t>(std::lround(clamped * 1000.0)), 1000u};
}

// The focal plane resolution (pixels per unit on the sensor) follows the
// pixels: COLMAP derives the focal length in pixels from it when the camera
// is not in its sensor database.
void scale_focal_plane_resolution(Exiv2::ExifData& exif, const StagedCopyChanges& changes) {
  double x = rational(find(exif, "Exif.Photo.FocalPlaneXResolution")).value_or(0.0);
  double y = rational(find(exif, "Exif.Photo.FocalPlaneYResolution")).value_or(0.0);
  if (changes.transposed) std::swap(x, y);
  if (x > 0.0) exif["Exif.Photo.FocalPlaneXResolution"] = to_urational(x * changes.scale);
  if (y > 0.0) exif["Exif.Photo.FocalPlaneYResolution"] = to_urational(y * changes.scale);
}

Exiv2::ExifData staged_copy_exif(const Exiv2::ExifData& original, const StagedCopyChanges& changes) {
  Exiv2::ExifData exif = original;
  Exiv2::ExifThumb(exif).erase();  // a thumbnail of the unturned photo
  for (const char* key : kImageStructureTags) erase_key(exif, key);
  exif["Exif.Image.Orientation"] = std::uint16_t{1};
  exif["Exif.Photo.PixelXDimension"] = static_cast<std::uint32_t>(changes.width);
  exif["Exif.Photo.PixelYDimension"] = static_cast<std::uint32_t>(changes.height);
  scale_focal_plane_resolution(exif, changes);
  if (changes.write_zero_altitude) {
    exif["Exif.GPSInfo.GPSAltitude"] = Exiv2::URational(0, 1);
    exif["Exif.GPSInfo.GPSAltitudeRef"] = std::string("0");
  }
  return exif;
}

// Walks the marker segments before the scan data. Returns the offset just
// after the SOS segment header, or 0 if the structure is broken before that.
std::size_t scan_data_offset(const std::vector<std::uint8_t>& jpeg) {
  if (jpeg.size() < 4 || jpeg[0] != 0xFF || jpeg[1] != 0xD8) return 0;
  std::size_t pos = 2;
  while (pos + 4 <= jpeg.size()) {
    if (jpeg[pos] != 0xFF) return 0;
    const std::uint8_t marker = jpeg[pos + 1];
    if (marker == 0xFF) {  // fill byte
      ++pos;
      continue;
    }
    const std::size_t length = std::size_t(jpeg[pos + 2]) << 8 | jpeg[pos + 3];
    if (length < 2 || pos + 2 + length > jpeg.size()) return 0;
    pos += 2 + length;
    if (marker == 0xDA) return pos;
  }
  return 0;
}

}  // namespace

ExifBlock::ExifBlock() : data_(std::make_unique<Exiv2::ExifData>()) {}
ExifBlock::~ExifBlock() = default;
ExifBlock::ExifBlock(ExifBlock&&) noexcept = default;
ExifBlock& ExifBlock::operator=(ExifBlock&&) noexcept = default;

bool ExifBlock::empty() const { return data_->empty(); }

ExifInfo ExifBlock::info() const {
  ExifInfo info;
  const Exiv2::ExifData& exif = *data_;
  try {
    const Exiv2::Exifdatum* orientation = find(exif, "Exif.Image.Orientation");
    if (orientation != nullptr && orientation->count() > 0) {
      const long o = orientation->toLong(0);
      if (o >= 1 && o <= 8) info.orientation = static_cast<int>(o);
    }
    const auto focal = rational(find(exif, "Exif.Photo.FocalLength"));
    if (focal && *focal > 0.0) info.focal_length_mm = focal;
    info.gps = gps_position(exif);
    info.camera_make = trimmed_text(find(exif, "Exif.Image.Make"));
    info.camera_model = trimmed_text(find(exif, "Exif.Image.Model"));
  } catch (const std::exception&) {
    // Malformed values: what was read so far stands.
  }
  return info;
}

ExifBlock read_exif(const std::vector<std::uint8_t>& file_bytes) {
  quiet_exiv2();
  ExifBlock block;
  if (file_bytes.empty()) return block;
  try {
    auto image = Exiv2::ImageFactory::open(file_bytes.data(), static_cast<long>(file_bytes.size()));
    if (image.get() == nullptr) return block;
    image->readMetadata();
    block.data() = image->exifData();
  } catch (const std::exception&) {
    block.data().clear();  // not a format exiv2 knows, or broken metadata
  }
  return block;
}

ExifBlock read_exif_tiff(const std::uint8_t* tiff, std::size_t size) {
  quiet_exiv2();
  ExifBlock block;
  if (tiff == nullptr || size < 8) return block;
  try {
    Exiv2::ExifParser::decode(block.data(), tiff, static_cast<std::uint32_t>(size));
  } catch (const std::exception&) {
    block.data().clear();
  }
  return block;
}

ExifInfo parse_jpeg_exif(const std::vector<std::uint8_t>& jpeg) { return read_exif(jpeg).info(); }

void write_staged_exif(const ExifBlock& original, const StagedCopyChanges& changes, const std::filesystem::path& copy) {
  if (original.empty()) return;
  quiet_exiv2();
  try {
    auto image = Exiv2::ImageFactory::open(copy.string());
    image->readMetadata();  // keeps the copy's own ICC profile and XMP
    image->setExifData(staged_copy_exif(original.data(), changes));
    image->writeMetadata();
  } catch (const std::exception& e) {
    throw OutputError(copy.string(), std::string("the photo's EXIF into its staged copy: ") + e.what());
  }
}

bool jpeg_is_complete(const std::vector<std::uint8_t>& jpeg) {
  const std::size_t scan = scan_data_offset(jpeg);
  if (scan == 0) return false;
  // In entropy-coded data 0xFF is always followed by 0x00 or a restart
  // marker, so the first FF D9 after the scan header is the end of image.
  for (std::size_t i = scan; i + 1 < jpeg.size(); ++i) {
    if (jpeg[i] == 0xFF && jpeg[i + 1] == 0xD9) return true;
  }
  return false;
}

std::vector<std::uint8_t> read_file_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "cannot be opened for reading");
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(path.string(), "read error");
  return bytes;
}

}  // namespace hos::sfm

#pragma GCC diagnostic pop
