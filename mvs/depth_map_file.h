// hos-mvs's .dmap files: a view's depth, normal and cost maps as fusion
// reads them back (hos-mvs --fuse) and the bench programs inspect them.
#pragma once

#include <filesystem>
#include <string>

#include "mvs/patch_match.h"

namespace hos::mvs {

// <folder>/<image name>.dmap
std::filesystem::path depth_map_file(const std::filesystem::path& folder, const std::string& name);

// A tag, width and height, then the depth, normal and cost rows as raw
// floats, so a map read back is the map written, bit for bit. Written
// atomically; throws OutputError naming the file.
void write_depth_map_file(const std::filesystem::path& file, const DepthMap& map);

// The map at its own size. Throws InputError naming the file when it is
// missing, not a depth map, truncated or longer than its size says.
DepthMap read_depth_map_file(const std::filesystem::path& file);

}  // namespace hos::mvs
