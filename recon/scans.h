// Inputs without per-point normals (paper sec. 5): registered range scans,
// where every point of a scan gets that scan's viewing direction, and point
// sets oriented by one view direction or scanner position.
#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <vector>

#include "core/reporter.h"
#include "core/types.h"

namespace hos::recon {

// One "bmesh FILE tx ty tz qx qy qz qw" line of a Stanford .conf file.
struct RangeScanEntry {
  std::filesystem::path file;  // resolved relative to the .conf file's folder
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  // as written (x y z w)

  // The Stanford files store the inverse rotation: p_world = R(q)^T p + t.
  Eigen::Vector3d to_world(const Eigen::Vector3d& p) const;
  // The scanner looks along -z of the scan's frame: +z points to the scanner.
  Eigen::Vector3d direction_to_scanner() const;
};

// Parses the .conf; throws InputError naming the file and line.
std::vector<RangeScanEntry> read_stanford_conf(const std::filesystem::path& conf);

// Loads every scan, transforms it to world coordinates and orients every
// point of a scan by that scan's direction to the scanner. The sign is checked
// against the data: a scan's points lie on the side of the object facing its
// scanner, so the direction must point from the centre of all points towards
// the scan's centroid; it is flipped (with a warning) otherwise.
PointCloud load_stanford_scans(const std::filesystem::path& conf, Reporter& reporter);

// Sets every normal to the unit direction towards the viewer.
void orient_by_view_direction(PointCloud& points, const Eigen::Vector3f& direction_to_viewer);
// Sets every normal to the unit direction from the point to the scanner.
void orient_by_scanner_position(PointCloud& points, const Eigen::Vector3f& scanner);

}  // namespace hos::recon
