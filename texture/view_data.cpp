#include "texture/view_data.h"

#include <algorithm>
#include <cstring>
#include <fstream>

#include "core/binary_file.h"
#include "core/binary_values.h"
#include "core/error.h"
#include "core/fnv1a.h"

namespace hos::texture {
namespace {

constexpr BinaryFileKind kViewDataKind{
    {'H', 'O', 'S', 'T', 'V', 'I', 'E', 'W'}, kViewDataVersion, "hos-texture", "view data", "compute it again"};

// One sample on disk: the face, then the seven floats of FaceViewSample
// (its view is the file's).
constexpr std::size_t kSampleFloats = 7;

}  // namespace

std::filesystem::path view_data_file(const std::filesystem::path& folder, const std::string& view_name) {
  return folder / (view_name + ".tvis");
}

std::uint64_t view_data_fingerprint(const TriangleMesh& mesh, const TextureView& view, const TextureOptions& options) {
  Fnv1a f;
  f.add(mesh.vertices.size());
  for (const auto& v : mesh.vertices) f.add(v);
  f.add(mesh.faces.size());
  for (const auto& face : mesh.faces) f.add(face);
  f.add(view.camera.width);
  f.add(view.camera.height);
  for (double p : view.camera.params) f.add(p);
  f.add(view.pose.cam_from_world_rotation.coeffs());
  f.add(view.pose.cam_from_world_translation);
  f.add(options.max_view_angle_deg);
  f.add(options.depth_tolerance);
  return f.value();
}

void write_view_data(const std::filesystem::path& file, const ViewDataKey& key, const ViewSamples& samples) {
  write_binary_file(file, kViewDataKind, [&](std::ofstream& out) {
    write_value(out, static_cast<std::int32_t>(key.view_index));
    write_value(out, static_cast<std::int32_t>(key.num_faces));
    write_value(out, key.fingerprint);
    write_value(out, static_cast<std::uint64_t>(samples.size()));
    for (const auto& [face, s] : samples) {
      write_value(out, static_cast<std::int32_t>(face));
      const float values[kSampleFloats] = {s.gradient_integral, s.visible_px,   s.projected_area_px, s.cos_angle,
                                           s.mean_rgb.x(),      s.mean_rgb.y(), s.mean_rgb.z()};
      out.write(reinterpret_cast<const char*>(values), sizeof(values));
    }
  });
}

ViewSamples read_view_data(const std::filesystem::path& file, const ViewDataKey& key) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    throw InputError(file.string(), "missing view data; compute it with hos-texture --views ... --view-data first");
  }
  read_binary_file_start(in, file, kViewDataKind);
  std::int32_t view_index = 0, num_faces = 0;
  std::uint64_t fingerprint = 0, count = 0;
  if (!read_value(in, view_index) || !read_value(in, num_faces) || !read_value(in, fingerprint) ||
      !read_value(in, count)) {
    throw InputError(file.string(), "truncated view data (the header is incomplete)");
  }
  if (view_index != key.view_index || num_faces != key.num_faces || fingerprint != key.fingerprint) {
    throw InputError(file.string(),
                     format_message("view data of view ", view_index, " on a mesh of ", num_faces,
                                    " faces does not belong to this run (view ", key.view_index, ", ", key.num_faces,
                                    " faces): computed from another mesh, model or options; compute it again"));
  }
  // Read the samples in blocks, so a damaged count cannot ask for memory the file does not hold.
  ViewSamples samples;
  constexpr std::size_t kRecordBytes = sizeof(std::int32_t) + kSampleFloats * sizeof(float);
  std::uint64_t read = 0;
  while (read < count) {
    const std::size_t block = static_cast<std::size_t>(std::min<std::uint64_t>(count - read, 4096));
    std::vector<char> bytes(block * kRecordBytes);
    if (!in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()))) {
      throw InputError(file.string(), format_message("truncated view data: ", read, " of ", count, " samples"));
    }
    for (std::size_t i = 0; i < block; ++i) {
      const char* record = bytes.data() + i * kRecordBytes;
      std::int32_t face = 0;
      float values[kSampleFloats];
      std::memcpy(&face, record, sizeof(face));
      std::memcpy(values, record + sizeof(face), sizeof(values));
      if (face < 0 || face >= num_faces || (!samples.empty() && face <= samples.back().first)) {
        throw InputError(file.string(), format_message("damaged view data: sample ", read + i, " names face ", face));
      }
      FaceViewSample s;
      s.view = view_index;
      s.gradient_integral = values[0];
      s.visible_px = values[1];
      s.projected_area_px = values[2];
      s.cos_angle = values[3];
      s.mean_rgb = Eigen::Vector3f(values[4], values[5], values[6]);
      samples.emplace_back(face, s);
    }
    read += block;
  }
  if (in.peek() != std::ifstream::traits_type::eof()) {
    throw InputError(file.string(), "damaged view data: bytes after the last sample");
  }
  return samples;
}

}  // namespace hos::texture
