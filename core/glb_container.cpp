#include "core/glb_container.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <nlohmann/json.hpp>
#include <vector>

#include "core/error.h"

namespace hos {
namespace {

constexpr std::uint32_t kMagic = 0x46546C67;      // "glTF"
constexpr std::uint32_t kJsonChunk = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kBinChunk = 0x004E4942;   // "BIN\0"
constexpr const char* kMeshopt = "EXT_meshopt_compression";

std::uint32_t read_u32(const std::string& bytes, std::size_t offset) {
  std::uint32_t value = 0;
  std::memcpy(&value, bytes.data() + offset, 4);
  return value;
}

void put_u32(std::string& out, std::uint32_t value) {
  char bytes[4];
  std::memcpy(bytes, &value, 4);
  out.append(bytes, 4);
}

void pad(std::string& bytes, char fill) {
  while (bytes.size() % 4 != 0) bytes.push_back(fill);
}

using Json = nlohmann::ordered_json;

// The decoded bytes (count x stride) of one compressed view's stream.
std::vector<unsigned char> decode_view(const Json& ext, const std::string& bin, const std::string& path) {
  const std::size_t offset = ext.value("byteOffset", std::size_t{0});
  const std::size_t length = ext.at("byteLength").get<std::size_t>();
  const std::size_t stride = ext.at("byteStride").get<std::size_t>();
  const std::size_t count = ext.at("count").get<std::size_t>();
  const std::string mode = ext.at("mode").get<std::string>();
  const std::string filter = ext.value("filter", std::string("NONE"));
  if (offset > bin.size() || length > bin.size() - offset) {
    throw InputError(path, "a meshopt-compressed buffer view reads past the end of the BIN chunk");
  }
  if (stride == 0 || stride > 256 || count > (std::size_t{1} << 32)) {
    throw InputError(path, "a meshopt-compressed buffer view has an invalid byteStride or count");
  }
  std::vector<unsigned char> out(count * stride);
  const auto* source = reinterpret_cast<const unsigned char*>(bin.data() + offset);
  int status = -1;
  if (mode == "ATTRIBUTES" && stride % 4 == 0) {
    status = meshopt_decodeVertexBuffer(out.data(), count, stride, source, length);
  } else if (mode == "TRIANGLES" && (stride == 2 || stride == 4) && count % 3 == 0) {
    status = meshopt_decodeIndexBuffer(out.data(), count, stride, source, length);
  } else if (mode == "INDICES" && (stride == 2 || stride == 4)) {
    status = meshopt_decodeIndexSequence(out.data(), count, stride, source, length);
  }
  if (status != 0) {
    throw InputError(path, "a meshopt-compressed buffer view (mode " + mode + ", byteStride " + std::to_string(stride) +
                               ") cannot be decoded");
  }
  if (filter == "OCTAHEDRAL" && (stride == 4 || stride == 8)) {
    meshopt_decodeFilterOct(out.data(), count, stride);
  } else if (filter == "QUATERNION" && stride == 8) {
    meshopt_decodeFilterQuat(out.data(), count, stride);
  } else if (filter == "EXPONENTIAL" && stride % 4 == 0) {
    meshopt_decodeFilterExp(out.data(), count, stride);
  } else if (filter != "NONE") {
    throw InputError(path, "a meshopt-compressed buffer view has an unknown filter " + filter);
  }
  return out;
}

bool is_fallback(const Json& buffer) {
  const auto extensions = buffer.find("extensions");
  if (extensions == buffer.end() || !extensions->contains(kMeshopt)) return false;
  return extensions->at(kMeshopt).value("fallback", false);
}

void drop_extension_name(Json& json, const char* list) {
  if (!json.contains(list)) return;
  Json& names = json[list];
  names.erase(std::remove(names.begin(), names.end(), Json(kMeshopt)), names.end());
  if (names.empty()) json.erase(list);
}

// Every fallback buffer removed, the buffer views' buffer indices moved
// along; throws if a view still reads one.
void remove_fallback_buffers(Json& json, const std::string& path) {
  std::vector<int> new_index;
  Json kept = Json::array();
  for (const Json& buffer : json["buffers"]) {
    new_index.push_back(is_fallback(buffer) ? -1 : static_cast<int>(kept.size()));
    if (new_index.back() >= 0) kept.push_back(buffer);
  }
  for (Json& view : json["bufferViews"]) {
    const int buffer = view.value("buffer", -1);
    if (buffer < 0 || buffer >= static_cast<int>(new_index.size()) || new_index[buffer] < 0) {
      throw InputError(path, "a buffer view reads a missing or fallback buffer without being meshopt-compressed");
    }
    view["buffer"] = new_index[buffer];
  }
  json["buffers"] = std::move(kept);
}

}  // namespace

GlbChunks split_glb(const std::string& glb, const std::string& path) {
  if (glb.size() < 20 || read_u32(glb, 0) != kMagic || read_u32(glb, 4) != 2) {
    throw InputError(path, "not a binary glTF 2.0 file");
  }
  const std::size_t total = std::min<std::size_t>(read_u32(glb, 8), glb.size());
  GlbChunks chunks;
  std::size_t at = 12;
  while (at + 8 <= total) {
    const std::size_t length = read_u32(glb, at);
    const std::uint32_t type = read_u32(glb, at + 4);
    if (length > total - at - 8) throw InputError(path, "a binary glTF chunk runs past the end of the file");
    if (type == kJsonChunk && at == 12) chunks.json = glb.substr(at + 8, length);
    if (type == kBinChunk && at > 12 && chunks.bin.empty()) chunks.bin = glb.substr(at + 8, length);
    at += 8 + length;
  }
  if (chunks.json.empty()) throw InputError(path, "a binary glTF file without its JSON chunk");
  return chunks;
}

std::vector<std::string> glb_required_extensions(const std::string& glb, const std::string& path) {
  const GlbChunks chunks = split_glb(glb, path);
  try {
    return Json::parse(chunks.json).value("extensionsRequired", std::vector<std::string>{});
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, std::string("malformed glTF JSON: ") + e.what());
  }
}

std::string join_glb(const std::string& json, const std::string& bin) {
  std::string json_chunk = json, bin_chunk = bin;
  pad(json_chunk, ' ');
  pad(bin_chunk, '\0');
  const std::size_t total = 12 + 8 + json_chunk.size() + (bin_chunk.empty() ? 0 : 8 + bin_chunk.size());
  std::string out;
  out.reserve(total);
  put_u32(out, kMagic);
  put_u32(out, 2);
  put_u32(out, static_cast<std::uint32_t>(total));
  put_u32(out, static_cast<std::uint32_t>(json_chunk.size()));
  put_u32(out, kJsonChunk);
  out += json_chunk;
  if (!bin_chunk.empty()) {
    put_u32(out, static_cast<std::uint32_t>(bin_chunk.size()));
    put_u32(out, kBinChunk);
    out += bin_chunk;
  }
  return out;
}

std::string decode_meshopt_glb(const std::string& glb, const std::string& path) {
  GlbChunks chunks = split_glb(glb, path);
  Json json;
  try {
    json = Json::parse(chunks.json);
    const Json used = json.value("extensionsUsed", Json::array());
    if (std::find(used.begin(), used.end(), Json(kMeshopt)) == used.end()) return glb;
    if (json.value("buffers", Json::array()).empty() || json["buffers"][0].contains("uri")) {
      throw InputError(path, "meshopt-compressed data outside the BIN chunk is not supported");
    }
    if (!json.contains("bufferViews")) json["bufferViews"] = Json::array();
    std::string& bin = chunks.bin;
    for (Json& view : json["bufferViews"]) {
      if (!view.contains("extensions") || !view["extensions"].contains(kMeshopt)) continue;
      const Json ext = view["extensions"][kMeshopt];
      if (ext.value("buffer", -1) != 0) {
        throw InputError(path, "meshopt-compressed data outside the BIN chunk is not supported");
      }
      const std::vector<unsigned char> decoded = decode_view(ext, bin, path);
      if (view.value("byteLength", std::size_t{0}) > decoded.size()) {
        throw InputError(path, "a meshopt-compressed buffer view is longer than its decoded data");
      }
      pad(bin, '\0');
      view["buffer"] = 0;
      view["byteOffset"] = bin.size();
      bin.append(reinterpret_cast<const char*>(decoded.data()), decoded.size());
      view["extensions"].erase(kMeshopt);
      if (view["extensions"].empty()) view.erase("extensions");
    }
    pad(bin, '\0');
    json["buffers"][0]["byteLength"] = bin.size();
    remove_fallback_buffers(json, path);
    drop_extension_name(json, "extensionsUsed");
    drop_extension_name(json, "extensionsRequired");
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, std::string("malformed glTF JSON: ") + e.what());
  }
  return join_glb(json.dump(), chunks.bin);
}

}  // namespace hos
