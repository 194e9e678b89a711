// Binary glTF (.glb) containers: the JSON and BIN chunks, and the decoding
// of EXT_meshopt_compression's buffer views (meshoptimizer's vertex and
// index codecs) into a plain .glb that any glTF reader (tinygltf) reads.
#pragma once

#include <string>
#include <vector>

namespace hos {

struct GlbChunks {
  std::string json;
  std::string bin;  // empty when the file has no BIN chunk
};

// Throws InputError naming path for a file that is not a version 2 .glb or
// whose chunks run past its end.
GlbChunks split_glb(const std::string& glb, const std::string& path);

// The names the .glb's JSON lists in extensionsRequired (the extensions a
// reader must support to load it), in file order. Throws InputError naming
// path for a file that is not a .glb or whose JSON is malformed.
std::vector<std::string> glb_required_extensions(const std::string& glb, const std::string& path);

// The .glb of the chunks: JSON padded with spaces, BIN with zeros, to 4 bytes.
std::string join_glb(const std::string& json, const std::string& bin);

// The .glb with every EXT_meshopt_compression buffer view decoded into the
// BIN chunk (filters OCTAHEDRAL, QUATERNION and EXPONENTIAL applied), the
// fallback buffers removed and the extension dropped from extensionsUsed
// and extensionsRequired; a file without the extension comes back as it is.
// Throws InputError naming path for a malformed or undecodable file (a
// compressed view outside the BIN chunk, a codec error, a buffer view that
// reads a fallback buffer without being compressed).
std::string decode_meshopt_glb(const std::string& glb, const std::string& path);

}  // namespace hos
