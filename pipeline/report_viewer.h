// The report's 3D view: the textured .glb in @google/model-viewer (vendored
// at build time, see pipeline/CMakeLists.txt) with the camera centres as
// hotspots that can be shown or hidden. Script and model are embedded in the
// page: browsers refuse scripts and fetches from file:// URLs otherwise.
#pragma once

#include <filesystem>
#include <string>

#include "pipeline/stage_paths.h"

namespace hos::pipeline {

// Where the build puts model-viewer's bundle, relative to the executables.
std::filesystem::path default_viewer_script(const std::filesystem::path& bin_dir);

// The viewer section; "" when the workspace has no textured model. Without
// the script (not built) the section is a link to the model.
std::string model_viewer_html(const StagePaths& paths, const std::filesystem::path& viewer_script);

// The whole file ("" if it cannot be read), for data: URIs and the page.
std::string read_bytes(const std::filesystem::path& file);

// Standard base64 (RFC 4648) of bytes, for data: URIs.
std::string base64(const std::string& bytes);

}  // namespace hos::pipeline
