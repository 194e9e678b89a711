#include "core/colmap_io.h"

#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "core/atomic_file.h"
#include "core/error.h"

namespace hos {
namespace fs = std::filesystem;
namespace {

// COLMAP marks a keypoint without a 3D point with the largest point3D_t.
constexpr std::uint64_t kInvalidPoint3dId = std::numeric_limits<std::uint64_t>::max();

// ---- binary -------------------------------------------------------------

// Reads little-endian values from a whole file held in memory; COLMAP writes
// its .bin files little-endian on every platform.
class BinaryReader {
 public:
  explicit BinaryReader(const fs::path& path) : path_(path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path.string(), "cannot open file");
    data_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }

  template <typename T>
  T read() {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof(T));
    T value;
    std::memcpy(&value, data_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return value;
  }

  std::string read_string() {
    const auto end = data_.find('\0', pos_);
    if (end == std::string::npos) fail("unterminated image name");
    std::string s = data_.substr(pos_, end - pos_);
    pos_ = end + 1;
    return s;
  }

  // Counts come from the file: refuse ones the remaining bytes cannot hold,
  // so a corrupt count is an error instead of a huge allocation.
  std::uint64_t read_count(std::size_t min_bytes_per_item) {
    const auto n = read<std::uint64_t>();
    if (min_bytes_per_item > 0 && n > (data_.size() - pos_) / min_bytes_per_item) {
      fail("count " + std::to_string(n) + " exceeds the file size (truncated or corrupt)");
    }
    return n;
  }

  void expect_end() const {
    if (pos_ != data_.size()) fail("unexpected data after the last record");
  }

  [[noreturn]] void fail(const std::string& reason) const {
    throw InputError(path_.string(), reason + " (at byte " + std::to_string(pos_) + ")");
  }

 private:
  void need(std::size_t n) const {
    if (data_.size() - pos_ < n) fail("file is truncated");
  }

  fs::path path_;
  std::string data_;
  std::size_t pos_ = 0;
};

class BinaryWriter {
 public:
  template <typename T>
  void write(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* bytes = reinterpret_cast<const char*>(&value);
    data_.append(bytes, sizeof(T));
  }
  void write_string(const std::string& s) {
    data_.append(s);
    data_.push_back('\0');
  }
  const std::string& data() const { return data_; }

 private:
  std::string data_;
};

void write_file(const fs::path& path, const std::string& contents) {
  write_atomically(path, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw OutputError(path.string(), "the file cannot be created");
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    if (!out) throw OutputError(path.string(), "write failed (disk full?)");
  });
}

Camera make_camera(const std::string& file, int id, CameraModel model, std::uint64_t width, std::uint64_t height) {
  if (width == 0 || height == 0 || width > 1'000'000 || height > 1'000'000) {
    throw InputError(file, "camera " + std::to_string(id) + " has invalid size " + std::to_string(width) + "x" +
                               std::to_string(height));
  }
  Camera camera;
  camera.id = id;
  camera.model = model;
  camera.width = static_cast<int>(width);
  camera.height = static_cast<int>(height);
  return camera;
}

void read_cameras_binary(const fs::path& path, SparseModel& model) {
  BinaryReader in(path);
  const auto n = in.read_count(24);
  for (std::uint64_t i = 0; i < n; ++i) {
    const auto id = static_cast<int>(in.read<std::uint32_t>());
    const int model_id = in.read<std::int32_t>();
    CameraModel camera_model;
    try {
      camera_model = camera_model_from_id(model_id);
    } catch (const std::invalid_argument& e) {
      in.fail(e.what());
    }
    const auto width = in.read<std::uint64_t>();
    const auto height = in.read<std::uint64_t>();
    Camera camera = make_camera(path.string(), id, camera_model, width, height);
    camera.params.resize(camera_model_num_params(camera_model));
    for (double& p : camera.params) p = in.read<double>();
    model.cameras[id] = std::move(camera);
  }
  in.expect_end();
}

void read_images_binary(const fs::path& path, SparseModel& model) {
  BinaryReader in(path);
  const auto n = in.read_count(64);
  for (std::uint64_t i = 0; i < n; ++i) {
    ImageRecord image;
    image.id = static_cast<int>(in.read<std::uint32_t>());
    const double qw = in.read<double>(), qx = in.read<double>(), qy = in.read<double>(), qz = in.read<double>();
    image.cam_from_world_rotation = Eigen::Quaterniond(qw, qx, qy, qz).normalized();
    for (int k = 0; k < 3; ++k) image.cam_from_world_translation[k] = in.read<double>();
    image.camera_id = static_cast<int>(in.read<std::uint32_t>());
    image.name = in.read_string();
    const auto num_points2d = in.read_count(24);
    image.keypoints.resize(num_points2d);
    for (auto& kp : image.keypoints) {
      kp.xy.x() = in.read<double>();
      kp.xy.y() = in.read<double>();
      const auto id = in.read<std::uint64_t>();
      kp.point3d_id = id == kInvalidPoint3dId ? -1 : static_cast<std::int64_t>(id);
    }
    model.images[image.id] = std::move(image);
  }
  in.expect_end();
}

void read_points_binary(const fs::path& path, SparseModel& model) {
  BinaryReader in(path);
  const auto n = in.read_count(51);
  for (std::uint64_t i = 0; i < n; ++i) {
    Point3D point;
    point.id = static_cast<std::int64_t>(in.read<std::uint64_t>());
    for (int k = 0; k < 3; ++k) point.xyz[k] = in.read<double>();
    for (int k = 0; k < 3; ++k) point.color[k] = in.read<std::uint8_t>();
    point.error = in.read<double>();
    const auto track_length = in.read_count(8);
    point.track.resize(track_length);
    for (auto& element : point.track) {
      element.image_id = static_cast<int>(in.read<std::uint32_t>());
      element.keypoint_index = static_cast<int>(in.read<std::uint32_t>());
    }
    model.points[point.id] = std::move(point);
  }
  in.expect_end();
}

// ---- text ----------------------------------------------------------------

// Iterates over the non-comment lines of a COLMAP text file, keeping line
// numbers for error messages.
class TextReader {
 public:
  explicit TextReader(const fs::path& path) : path_(path), in_(path) {
    if (!in_) throw InputError(path.string(), "cannot open file");
  }

  // Next line that is not a comment; blank lines are returned only when
  // keep_blank (images.txt has an empty keypoint line for images without any).
  bool next(std::string& line, bool keep_blank = false) {
    while (std::getline(in_, line)) {
      ++line_number_;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      const auto first = line.find_first_not_of(" \t");
      if (first == std::string::npos) {
        if (keep_blank) return true;
        continue;
      }
      if (line[first] == '#') continue;
      return true;
    }
    return false;
  }

  [[noreturn]] void fail(const std::string& reason) const {
    throw InputError(path_.string(), "line " + std::to_string(line_number_) + ": " + reason);
  }

 private:
  fs::path path_;
  std::ifstream in_;
  int line_number_ = 0;
};

template <typename T>
T parse_field(std::istringstream& s, const TextReader& reader, const char* what) {
  T value;
  if (!(s >> value)) reader.fail(std::string("cannot read ") + what);
  return value;
}

void read_cameras_text(const fs::path& path, SparseModel& model) {
  TextReader reader(path);
  std::string line;
  while (reader.next(line)) {
    std::istringstream s(line);
    const int id = parse_field<int>(s, reader, "camera id");
    const auto model_name = parse_field<std::string>(s, reader, "camera model");
    CameraModel camera_model;
    try {
      camera_model = camera_model_from_name(model_name);
    } catch (const std::invalid_argument& e) {
      reader.fail(e.what());
    }
    const auto width = parse_field<std::uint64_t>(s, reader, "width");
    const auto height = parse_field<std::uint64_t>(s, reader, "height");
    Camera camera = make_camera(path.string(), id, camera_model, width, height);
    camera.params.resize(camera_model_num_params(camera_model));
    for (double& p : camera.params) p = parse_field<double>(s, reader, "camera parameter");
    model.cameras[id] = std::move(camera);
  }
}

void read_images_text(const fs::path& path, SparseModel& model) {
  TextReader reader(path);
  std::string line;
  while (reader.next(line)) {
    std::istringstream s(line);
    ImageRecord image;
    image.id = parse_field<int>(s, reader, "image id");
    double q[4];
    for (double& v : q) v = parse_field<double>(s, reader, "quaternion");
    image.cam_from_world_rotation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
    for (int k = 0; k < 3; ++k) {
      image.cam_from_world_translation[k] = parse_field<double>(s, reader, "translation");
    }
    image.camera_id = parse_field<int>(s, reader, "camera id");
    // The name is the rest of the line (it may contain spaces).
    std::string name;
    std::getline(s >> std::ws, name);
    if (name.empty()) reader.fail("missing image name");
    image.name = name;
    if (!reader.next(line, /*keep_blank=*/true)) reader.fail("missing keypoint line");
    std::istringstream points(line);
    double x, y;
    std::int64_t id;
    while (points >> x >> y >> id) image.keypoints.push_back({Eigen::Vector2d(x, y), id});
    if (!points.eof()) reader.fail("malformed keypoint list");
    model.images[image.id] = std::move(image);
  }
}

void read_points_text(const fs::path& path, SparseModel& model) {
  TextReader reader(path);
  std::string line;
  while (reader.next(line)) {
    std::istringstream s(line);
    Point3D point;
    point.id = parse_field<std::int64_t>(s, reader, "point id");
    for (int k = 0; k < 3; ++k) point.xyz[k] = parse_field<double>(s, reader, "coordinate");
    for (int k = 0; k < 3; ++k) {
      const int c = parse_field<int>(s, reader, "colour");
      if (c < 0 || c > 255) reader.fail("colour out of range");
      point.color[k] = static_cast<std::uint8_t>(c);
    }
    point.error = parse_field<double>(s, reader, "error");
    int image_id, keypoint_index;
    while (s >> image_id >> keypoint_index) point.track.push_back({image_id, keypoint_index});
    if (!s.eof()) reader.fail("malformed track");
    model.points[point.id] = std::move(point);
  }
}

// Every reference inside the model must resolve: a model that points to a
// camera or image that does not exist is corrupt, and later stages would crash.
void check_references(const fs::path& folder, const SparseModel& model) {
  for (const auto& [id, image] : model.images) {
    if (!model.cameras.count(image.camera_id)) {
      throw InputError(folder.string(),
                       "image '" + image.name + "' refers to missing camera " + std::to_string(image.camera_id));
    }
  }
  for (const auto& [id, point] : model.points) {
    for (const auto& element : point.track) {
      if (!model.images.count(element.image_id)) {
        throw InputError(folder.string(), "point " + std::to_string(id) + " refers to missing image " +
                                              std::to_string(element.image_id));
      }
    }
  }
}

fs::path require_file(const fs::path& folder, const std::string& name) {
  fs::path path = folder / name;
  if (!fs::is_regular_file(path)) throw InputError(path.string(), "file is missing");
  return path;
}

std::string cameras_text(const SparseModel& model) {
  std::ostringstream out;
  out << std::setprecision(17);
  out << "# Camera list with one line of data per camera:\n"
      << "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
      << "# Number of cameras: " << model.cameras.size() << "\n";
  for (const auto& [id, camera] : model.cameras) {
    out << id << ' ' << camera_model_name(camera.model) << ' ' << camera.width << ' ' << camera.height;
    for (double p : camera.params) out << ' ' << p;
    out << '\n';
  }
  return out.str();
}

std::string images_text(const SparseModel& model) {
  std::ostringstream out;
  out << std::setprecision(17);
  out << "# Image list with two lines of data per image:\n"
      << "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
      << "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
      << "# Number of images: " << model.images.size() << "\n";
  for (const auto& [id, image] : model.images) {
    const auto& q = image.cam_from_world_rotation;
    const auto& t = image.cam_from_world_translation;
    out << id << ' ' << q.w() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << t.x() << ' ' << t.y() << ' '
        << t.z() << ' ' << image.camera_id << ' ' << image.name << '\n';
    for (std::size_t k = 0; k < image.keypoints.size(); ++k) {
      const auto& kp = image.keypoints[k];
      out << (k ? " " : "") << kp.xy.x() << ' ' << kp.xy.y() << ' ' << kp.point3d_id;
    }
    out << '\n';
  }
  return out.str();
}

std::string points_text(const SparseModel& model) {
  std::ostringstream out;
  out << std::setprecision(17);
  out << "# 3D point list with one line of data per point:\n"
      << "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
      << "# Number of points: " << model.points.size() << "\n";
  for (const auto& [id, point] : model.points) {
    out << id << ' ' << point.xyz.x() << ' ' << point.xyz.y() << ' ' << point.xyz.z() << ' ' << int(point.color[0])
        << ' ' << int(point.color[1]) << ' ' << int(point.color[2]) << ' ' << point.error;
    for (const auto& e : point.track) out << ' ' << e.image_id << ' ' << e.keypoint_index;
    out << '\n';
  }
  return out.str();
}

std::string cameras_binary(const SparseModel& model) {
  BinaryWriter out;
  out.write<std::uint64_t>(model.cameras.size());
  for (const auto& [id, camera] : model.cameras) {
    out.write<std::uint32_t>(static_cast<std::uint32_t>(id));
    out.write<std::int32_t>(static_cast<std::int32_t>(camera.model));
    out.write<std::uint64_t>(static_cast<std::uint64_t>(camera.width));
    out.write<std::uint64_t>(static_cast<std::uint64_t>(camera.height));
    for (double p : camera.params) out.write(p);
  }
  return out.data();
}

std::string images_binary(const SparseModel& model) {
  BinaryWriter out;
  out.write<std::uint64_t>(model.images.size());
  for (const auto& [id, image] : model.images) {
    out.write<std::uint32_t>(static_cast<std::uint32_t>(id));
    const auto& q = image.cam_from_world_rotation;
    for (double v : {q.w(), q.x(), q.y(), q.z()}) out.write(v);
    for (int k = 0; k < 3; ++k) out.write(image.cam_from_world_translation[k]);
    out.write<std::uint32_t>(static_cast<std::uint32_t>(image.camera_id));
    out.write_string(image.name);
    out.write<std::uint64_t>(image.keypoints.size());
    for (const auto& kp : image.keypoints) {
      out.write(kp.xy.x());
      out.write(kp.xy.y());
      out.write<std::uint64_t>(kp.point3d_id < 0 ? kInvalidPoint3dId : static_cast<std::uint64_t>(kp.point3d_id));
    }
  }
  return out.data();
}

std::string points_binary(const SparseModel& model) {
  BinaryWriter out;
  out.write<std::uint64_t>(model.points.size());
  for (const auto& [id, point] : model.points) {
    out.write<std::uint64_t>(static_cast<std::uint64_t>(id));
    for (int k = 0; k < 3; ++k) out.write(point.xyz[k]);
    for (int k = 0; k < 3; ++k) out.write(point.color[k]);
    out.write(point.error);
    out.write<std::uint64_t>(point.track.size());
    for (const auto& e : point.track) {
      out.write<std::uint32_t>(static_cast<std::uint32_t>(e.image_id));
      out.write<std::uint32_t>(static_cast<std::uint32_t>(e.keypoint_index));
    }
  }
  return out.data();
}

}  // namespace

SparseModel read_colmap_model_binary(const fs::path& folder) {
  SparseModel model;
  read_cameras_binary(require_file(folder, "cameras.bin"), model);
  read_images_binary(require_file(folder, "images.bin"), model);
  read_points_binary(require_file(folder, "points3D.bin"), model);
  check_references(folder, model);
  return model;
}

SparseModel read_colmap_model_text(const fs::path& folder) {
  SparseModel model;
  read_cameras_text(require_file(folder, "cameras.txt"), model);
  read_images_text(require_file(folder, "images.txt"), model);
  read_points_text(require_file(folder, "points3D.txt"), model);
  check_references(folder, model);
  return model;
}

SparseModel read_colmap_model(const fs::path& folder) {
  if (!fs::is_directory(folder)) throw InputError(folder.string(), "model folder does not exist");
  if (fs::exists(folder / "cameras.bin")) return read_colmap_model_binary(folder);
  if (fs::exists(folder / "cameras.txt")) return read_colmap_model_text(folder);
  throw InputError(folder.string(), "no COLMAP model here (expected cameras, images and points3D as .bin or .txt)");
}

void write_colmap_model(const SparseModel& model, const fs::path& folder, ColmapFormat format) {
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw OutputError(folder.string(), ec.message());
  if (format == ColmapFormat::kText) {
    write_file(folder / "cameras.txt", cameras_text(model));
    write_file(folder / "images.txt", images_text(model));
    write_file(folder / "points3D.txt", points_text(model));
  } else {
    write_file(folder / "cameras.bin", cameras_binary(model));
    write_file(folder / "images.bin", images_binary(model));
    write_file(folder / "points3D.bin", points_binary(model));
  }
}

}  // namespace hos
