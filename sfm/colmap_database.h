// Reading back what COLMAP's feature extraction and matching wrote into its
// database (SQLite, WS/sfm/database.db): the images with their cameras and
// position priors, and how well each image matched the others. Lets the
// stage check that EXIF positions reached COLMAP and say why a photo did not
// register.
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace hos::sfm {

struct DatabaseImage {
  int id = 0;
  std::string name;
  int camera_id = 0;
  // COLMAP 3.8's images.prior_tx/ty/tz: latitude, longitude, altitude from
  // EXIF GPS; absent (NULL) when the photo had no complete EXIF position.
  std::optional<std::array<double, 3>> position_prior;
};

// Every image of the database, by id. Throws StageError when the database
// cannot be read.
std::vector<DatabaseImage> read_database_images(const std::filesystem::path& database);

// Per image name: the most verified matches (two-view geometry inliers) it
// has with any one other image; 0 for an image that matched none.
std::map<std::string, int> best_verified_matches(const std::filesystem::path& database);

}  // namespace hos::sfm
