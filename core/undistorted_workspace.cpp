#include "core/undistorted_workspace.h"

#include "core/colmap_io.h"
#include "core/error.h"

namespace hos {
namespace fs = std::filesystem;

UndistortedWorkspace load_undistorted_workspace(const fs::path& root) {
  if (!fs::is_directory(root)) throw InputError(root.string(), "workspace folder does not exist");
  UndistortedWorkspace ws;
  ws.root = root;
  ws.image_folder = root / "images";
  if (!fs::is_directory(ws.image_folder)) {
    throw InputError(ws.image_folder.string(), "image folder of the workspace is missing");
  }
  ws.model = read_colmap_model(root / "sparse");
  if (ws.model.images.empty()) {
    throw InputError((root / "sparse").string(), "the model has no registered images");
  }
  for (const auto& [id, camera] : ws.model.cameras) {
    if (camera.model != CameraModel::kPinhole && camera.model != CameraModel::kSimplePinhole) {
      throw InputError((root / "sparse").string(), "camera " + std::to_string(id) + " is " +
                                                       camera_model_name(camera.model) +
                                                       ", expected undistorted PINHOLE cameras (run COLMAP's "
                                                       "image_undistorter first)");
    }
  }
  for (const auto& [id, image] : ws.model.images) {
    const fs::path path = ws.image_path(image);
    if (!fs::is_regular_file(path)) {
      throw InputError(path.string(), "image '" + image.name + "' of the model is missing");
    }
  }
  return ws;
}

}  // namespace hos
