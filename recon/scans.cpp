#include "recon/scans.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/ply_io.h"

namespace hos::recon {
namespace fs = std::filesystem;

Eigen::Vector3d RangeScanEntry::to_world(const Eigen::Vector3d& p) const {
  return rotation.conjugate() * p + translation;
}

Eigen::Vector3d RangeScanEntry::direction_to_scanner() const { return rotation.conjugate() * Eigen::Vector3d::UnitZ(); }

std::vector<RangeScanEntry> read_stanford_conf(const fs::path& conf) {
  std::ifstream in(conf);
  if (!in) throw InputError(conf.string(), "cannot open the scan list");
  std::vector<RangeScanEntry> scans;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    std::istringstream s(line);
    std::string keyword;
    if (!(s >> keyword) || keyword != "bmesh") continue;  // camera/mesh lines are not scans
    RangeScanEntry entry;
    std::string file;
    double t[3], q[4];
    if (!(s >> file >> t[0] >> t[1] >> t[2] >> q[0] >> q[1] >> q[2] >> q[3])) {
      throw InputError(conf.string(),
                       "line " + std::to_string(line_number) + ": expected 'bmesh FILE tx ty tz qx qy qz qw'");
    }
    if (!std::isfinite(t[0] + t[1] + t[2]) || !std::isfinite(q[0] + q[1] + q[2] + q[3])) {
      throw InputError(conf.string(), "line " + std::to_string(line_number) + ": the pose holds a non-finite number");
    }
    entry.file = conf.parent_path() / file;
    entry.translation = Eigen::Vector3d(t[0], t[1], t[2]);
    const Eigen::Quaterniond rotation(q[3], q[0], q[1], q[2]);
    if (!(rotation.norm() > 0.5)) {
      throw InputError(conf.string(), "line " + std::to_string(line_number) + ": the quaternion is not a rotation");
    }
    entry.rotation = rotation.normalized();
    scans.push_back(entry);
  }
  if (scans.empty()) throw InputError(conf.string(), "no 'bmesh' lines: the scan list is empty");
  return scans;
}

PointCloud load_stanford_scans(const fs::path& conf, Reporter& reporter) {
  const auto scans = read_stanford_conf(conf);
  std::vector<PointCloud> clouds;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  std::size_t total = 0;
  for (const auto& scan : scans) {
    PlyReadReport read_report;
    PointCloud cloud = read_point_cloud_ply(scan.file, &read_report);
    if (read_report.num_skipped_nonfinite > 0) {
      reporter.warn(
          format_message(scan.file.string(), ": skipped ", read_report.num_skipped_nonfinite, " non-finite points"));
    }
    for (auto& p : cloud.positions) {
      p = scan.to_world(p.cast<double>()).cast<float>();
      if (!p.allFinite()) {
        throw InputError(conf.string(),
                         scan.file.filename().string() + ": its pose moves points beyond the float range");
      }
      centre += p.cast<double>();
    }
    total += cloud.size();
    clouds.push_back(std::move(cloud));
  }
  if (total == 0) throw InputError(conf.string(), "the scans hold no points");
  centre /= static_cast<double>(total);

  PointCloud all;
  for (std::size_t s = 0; s < scans.size(); ++s) {
    const PointCloud& cloud = clouds[s];
    if (cloud.empty()) continue;
    Eigen::Vector3d scan_centre = Eigen::Vector3d::Zero();
    for (const auto& p : cloud.positions) scan_centre += p.cast<double>();
    scan_centre /= static_cast<double>(cloud.size());
    Eigen::Vector3d direction = scans[s].direction_to_scanner();
    if (direction.dot(scan_centre - centre) < 0.0) {
      reporter.warn(
          format_message(scans[s].file.filename().string(), ": the scanner direction points into the object; flipped"));
      direction = -direction;
    }
    const Eigen::Vector3f n = direction.cast<float>();
    all.positions.insert(all.positions.end(), cloud.positions.begin(), cloud.positions.end());
    all.normals.insert(all.normals.end(), cloud.size(), n);
  }
  reporter.info(format_message("read ", scans.size(), " scans, ", all.size(), " points from ", conf.string()));
  return all;
}

void orient_by_view_direction(PointCloud& points, const Eigen::Vector3f& direction_to_viewer) {
  const Eigen::Vector3f n = direction_to_viewer.normalized();
  points.normals.assign(points.size(), n);
}

void orient_by_scanner_position(PointCloud& points, const Eigen::Vector3f& scanner) {
  points.normals.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    points.normals[i] = (scanner - points.positions[i]).normalized();
  }
}

}  // namespace hos::recon
