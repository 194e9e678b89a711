// The undistorted workspace the sfm stage writes (COLMAP image_undistorter
// layout) and the mvs and texture stages read:
//   <root>/images/<image name>       undistorted photos
//   <root>/sparse/{cameras,images,points3D}.{bin,txt}   PINHOLE model
// hos-synth writes the same layout with ground-truth cameras.
#pragma once

#include <filesystem>

#include "core/sparse_model.h"

namespace hos {

struct UndistortedWorkspace {
  std::filesystem::path root;
  std::filesystem::path image_folder;  // root/images
  SparseModel model;

  std::filesystem::path image_path(const ImageRecord& image) const { return image_folder / image.name; }
};

// Loads and checks the workspace: the model must exist and every camera be
// undistorted (PINHOLE or SIMPLE_PINHOLE); every registered image's file must
// exist. Throws InputError naming the missing or malformed file.
UndistortedWorkspace load_undistorted_workspace(const std::filesystem::path& root);

}  // namespace hos
