#include "core/reference_cameras.h"

#include <fstream>

#include "core/error.h"

namespace hos {
namespace fs = std::filesystem;

std::map<std::string, ReferencePose> read_strecha_cameras(const fs::path& folder) {
  if (!fs::is_directory(folder)) throw InputError(folder.string(), "not a folder of Strecha .camera files");
  std::map<std::string, ReferencePose> poses;
  const std::string suffix = ".camera";
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::string file = entry.path().filename().string();
    if (file.size() <= suffix.size() || file.substr(file.size() - suffix.size()) != suffix) continue;
    std::ifstream in(entry.path());
    double v[9 + 3 + 9 + 3];
    for (double& x : v) in >> x;
    if (!in) throw InputError(entry.path().string(), "not a Strecha .camera file");
    Eigen::Matrix3d world_from_cam;
    for (int i = 0; i < 9; ++i) world_from_cam(i / 3, i % 3) = v[12 + i];
    poses[file.substr(0, file.size() - suffix.size())] = {world_from_cam.transpose(),
                                                          Eigen::Vector3d(v[21], v[22], v[23])};
  }
  if (poses.empty()) throw InputError(folder.string(), "no .camera files");
  return poses;
}

std::map<std::string, ReferencePose> read_middlebury_cameras(const fs::path& par_file) {
  std::ifstream in(par_file);
  int count = 0;
  if (!(in >> count) || count < 0) throw InputError(par_file.string(), "not a Middlebury _par.txt file");
  std::map<std::string, ReferencePose> poses;
  for (int n = 0; n < count; ++n) {
    std::string name;
    double k[9], r[9], t[3];
    in >> name;
    for (double& x : k) in >> x;
    for (double& x : r) in >> x;
    for (double& x : t) in >> x;
    if (!in) throw InputError(par_file.string(), "truncated at camera " + std::to_string(n + 1));
    Eigen::Matrix3d rotation;
    for (int i = 0; i < 9; ++i) rotation(i / 3, i % 3) = r[i];
    poses[name] = {rotation, -rotation.transpose() * Eigen::Vector3d(t[0], t[1], t[2])};
  }
  return poses;
}

}  // namespace hos
