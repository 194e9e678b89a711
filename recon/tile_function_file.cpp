#include "recon/tile_function_file.h"

#include <cstdio>

#include "core/binary_file.h"
#include "core/binary_values.h"
#include "core/error.h"
#include "core/reporter.h"

namespace hos::recon {
namespace {

constexpr BinaryFileKind kTileFunctionKind{{'H', 'O', 'S', 'T', 'I', 'L', 'E', 'F'},
                                           kTileFunctionVersion,
                                           "hos-recon",
                                           "tile function",
                                           "solve the tile again"};

std::string box_text(const NodeBox& b) {
  return format_message(b.lo.x(), ",", b.lo.y(), ",", b.lo.z(), " .. ", b.hi.x(), ",", b.hi.y(), ",", b.hi.z());
}

}  // namespace

std::filesystem::path tile_function_file(const std::filesystem::path& folder, int tile) {
  char name[32];
  std::snprintf(name, sizeof(name), "tile-%04d.htf", tile);
  return folder / name;
}

void write_tile_function(const std::filesystem::path& file,
                         const TileFunctionHeader& header,
                         const std::vector<float>& values) {
  write_binary_file(file, kTileFunctionKind, [&](std::ofstream& out) {
    write_value(out, static_cast<std::int32_t>(header.tile));
    write_value(out, static_cast<std::int32_t>(header.num_tiles));
    write_value(out, header.fingerprint);
    for (int a = 0; a < 3; ++a) write_value(out, static_cast<std::int32_t>(header.box.lo[a]));
    for (int a = 0; a < 3; ++a) write_value(out, static_cast<std::int32_t>(header.box.hi[a]));
    write_value(out, header.isovalue);
    write_value(out, header.gradient_scale);
    write_value(out, static_cast<std::uint64_t>(values.size()));
    out.write(reinterpret_cast<const char*>(values.data()),
              static_cast<std::streamsize>(values.size() * sizeof(float)));
  });
}

TileFunctionReader::TileFunctionReader(const std::filesystem::path& file, const TileFunctionHeader& expected)
    : file_(file), in_(file, std::ios::binary) {
  const std::string name = file.string();
  if (!in_) {
    throw InputError(name, format_message("missing tile function; solve it with hos-recon --tile ", expected.tile,
                                          " --tile-dir ", file.parent_path().string(), " first"));
  }
  read_binary_file_start(in_, file, kTileFunctionKind);
  std::int32_t tile = 0, tiles = 0;
  std::int32_t box[6] = {};
  std::uint64_t count = 0;
  bool ok = read_value(in_, tile) && read_value(in_, tiles) && read_value(in_, header_.fingerprint);
  for (std::int32_t& b : box) ok = ok && read_value(in_, b);
  ok = ok && read_value(in_, header_.isovalue) && read_value(in_, header_.gradient_scale) && read_value(in_, count);
  if (!ok) throw InputError(name, "truncated tile function (the header is incomplete)");
  header_.tile = tile;
  header_.num_tiles = tiles;
  header_.box = NodeBox{Eigen::Vector3i(box[0], box[1], box[2]), Eigen::Vector3i(box[3], box[4], box[5])};
  if (tile != expected.tile || tiles != expected.num_tiles || header_.fingerprint != expected.fingerprint ||
      header_.box.lo != expected.box.lo || header_.box.hi != expected.box.hi) {
    throw InputError(name, format_message("tile function of tile ", tile, " of ", tiles, " (nodes ",
                                          box_text(header_.box), ") does not belong to this run (tile ", expected.tile,
                                          " of ", expected.num_tiles, ", nodes ", box_text(expected.box),
                                          "): solved from other points or options; solve it again"));
  }
  data_offset_ = in_.tellg();
  const auto expected_bytes = static_cast<std::uintmax_t>(data_offset_) + header_.box.num_nodes() * sizeof(float);
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(file, error);
  if (error || count != static_cast<std::uint64_t>(header_.box.num_nodes()) || size != expected_bytes) {
    throw InputError(name, format_message(size < expected_bytes ? "truncated" : "damaged", " tile function: ", size,
                                          " bytes, expected ", expected_bytes, " for ", header_.box.num_nodes(),
                                          " values; solve the tile again"));
  }
}

std::vector<float> TileFunctionReader::read(const NodeBox& part) {
  const NodeBox& box = header_.box;
  std::vector<float> values(static_cast<std::size_t>(part.num_nodes()));
  if (part.empty()) return values;
  const std::int64_t nx = box.hi.x() - box.lo.x() + 1, ny = box.hi.y() - box.lo.y() + 1;
  const int row = part.hi.x() - part.lo.x() + 1;
  float* out = values.data();
  for (int k = part.lo.z(); k <= part.hi.z(); ++k) {
    for (int j = part.lo.y(); j <= part.hi.y(); ++j, out += row) {
      const std::int64_t first = ((k - box.lo.z()) * ny + (j - box.lo.y())) * nx + (part.lo.x() - box.lo.x());
      in_.seekg(data_offset_ + static_cast<std::streamoff>(first * sizeof(float)));
      if (!in_.read(reinterpret_cast<char*>(out), static_cast<std::streamsize>(row * sizeof(float)))) {
        throw InputError(file_.string(), "cannot read the tile function");
      }
    }
  }
  return values;
}

}  // namespace hos::recon
