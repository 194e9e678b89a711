// Sanity check of dense points from a photo set with calibrated cameras but
// no ground-truth surface (the Middlebury multi-view sets): aligns the sfm
// model to the calibrated cameras by a similarity over the camera centres
// (Umeyama 1991) and counts the points inside the object's bounding box.
//
//   hos-mvs-box-check SPARSE_DIR POINTS.ply PAR_FILE xmin ymin zmin xmax ymax zmax
//
// PAR_FILE: "count" then per image "name K(9) R(9) t(3)", x ~ K [R | t].
#include <Eigen/Geometry>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>

#include "core/colmap_io.h"
#include "core/ply_io.h"
#include "core/reference_cameras.h"

int main(int argc, char** argv) {
  if (argc != 10) {
    std::cerr << "usage: hos-mvs-box-check SPARSE_DIR POINTS.ply PAR_FILE xmin ymin zmin xmax ymax zmax\n";
    return 2;
  }
  try {
    const hos::SparseModel model = hos::read_colmap_model(argv[1]);
    const hos::PointCloud cloud = hos::read_point_cloud_ply(argv[2]);
    std::map<std::string, Eigen::Vector3d> true_centres;
    for (const auto& [name, pose] : hos::read_middlebury_cameras(argv[3])) true_centres[name] = pose.centre;
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pairs;
    for (const auto& [id, image] : model.images) {
      const auto it = true_centres.find(image.name);
      if (it != true_centres.end()) pairs.emplace_back(image.center(), it->second);
    }
    if (pairs.size() < 3) throw std::runtime_error("fewer than 3 images shared with the calibration");
    Eigen::Matrix3Xd from(3, pairs.size()), to(3, pairs.size());
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      from.col(i) = pairs[i].first;
      to.col(i) = pairs[i].second;
    }
    const Eigen::Matrix4d similarity = Eigen::umeyama(from, to, true);
    double centre_error = 0;
    for (const auto& [a, b] : pairs)
      centre_error = std::max(centre_error, ((similarity * a.homogeneous()).head<3>() - b).norm());
    const Eigen::Vector3d lo(std::atof(argv[4]), std::atof(argv[5]), std::atof(argv[6]));
    const Eigen::Vector3d hi(std::atof(argv[7]), std::atof(argv[8]), std::atof(argv[9]));
    const double diagonal = (hi - lo).norm();
    std::cout << pairs.size() << " cameras aligned, largest centre error " << centre_error / diagonal * 100
              << "% of the box diagonal\n";
    for (const double margin : {0.0, 0.01, 0.05}) {
      std::size_t inside = 0;
      for (const auto& p : cloud.positions) {
        const Eigen::Vector3d q = (similarity * p.cast<double>().homogeneous()).head<3>();
        inside +=
            (q.array() >= lo.array() - margin * diagonal).all() && (q.array() <= hi.array() + margin * diagonal).all();
      }
      std::cout << "inside the box + " << margin * 100 << "% of its diagonal: " << inside << " of " << cloud.size()
                << " (" << 100.0 * inside / std::max<std::size_t>(1, cloud.size()) << "%)\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "hos-mvs-box-check: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
