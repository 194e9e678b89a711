#include "texture/geo_alignment.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>
#include <sstream>

#include "core/error.h"
#include "core/json_report.h"
#include "core/nearest_rotation.h"
#include "core/photo_gps_json.h"
#include "core/reporter.h"
#include "core/statistics.h"

namespace hos::texture {
namespace {

template <int Dim>
struct Fit {
  double scale = 1.0;
  Eigen::Matrix<double, Dim, Dim> rotation = Eigen::Matrix<double, Dim, Dim>::Identity();
  Eigen::Matrix<double, Dim, 1> translation = Eigen::Matrix<double, Dim, 1>::Zero();
  std::vector<int> inliers;
  Eigen::Matrix<double, Dim, 1> operator()(const Eigen::Matrix<double, Dim, 1>& x) const {
    return scale * (rotation * x) + translation;
  }
};

template <int Dim>
using Points = Eigen::Matrix<double, Dim, Eigen::Dynamic>;

// Umeyama's least-squares similarity taking the chosen columns of from onto
// to (Umeyama 1991, Eqs. 40-42).
template <int Dim>
std::optional<Fit<Dim>> fit_similarity(const Points<Dim>& from, const Points<Dim>& to, const std::vector<int>& which) {
  using Vector = Eigen::Matrix<double, Dim, 1>;
  using Matrix = Eigen::Matrix<double, Dim, Dim>;
  const double n = static_cast<double>(which.size());
  Vector mean_from = Vector::Zero(), mean_to = Vector::Zero();
  for (int i : which) mean_from += from.col(i), mean_to += to.col(i);
  mean_from /= n;
  mean_to /= n;
  Matrix covariance = Matrix::Zero();
  double variance = 0.0;
  for (int i : which) {
    covariance += (to.col(i) - mean_to) * (from.col(i) - mean_from).transpose();
    variance += (from.col(i) - mean_from).squaredNorm();
  }
  covariance /= n;
  variance /= n;
  if (!(variance > 1e-24)) return std::nullopt;
  Fit<Dim> fit;
  fit.rotation = nearest_rotation(covariance);
  // Eq. 42: trace(D S) / variance, where trace(D S) = trace(R^T C).
  fit.scale = (fit.rotation.transpose() * covariance).trace() / variance;
  fit.translation = mean_to - fit.scale * (fit.rotation * mean_from);
  if (!(fit.scale > 1e-12) || !fit.rotation.allFinite() || !fit.translation.allFinite()) return std::nullopt;
  return fit;
}

// Within threshold horizontally and, in 3D, kVerticalTolerance times it
// vertically: GPS altitude is several times noisier than the position.
constexpr double kVerticalTolerance = 3.0;

template <int Dim>
bool is_inlier(const Eigen::Matrix<double, Dim, 1>& residual, double threshold) {
  if constexpr (Dim == 3) {
    return residual.template head<2>().norm() <= threshold && std::abs(residual.z()) <= kVerticalTolerance * threshold;
  } else {
    return residual.norm() <= threshold;
  }
}

template <int Dim>
std::vector<int> inliers_of(const Fit<Dim>& fit, const Points<Dim>& from, const Points<Dim>& to, double threshold) {
  std::vector<int> out;
  for (Eigen::Index i = 0; i < from.cols(); ++i) {
    if (is_inlier<Dim>(fit(from.col(i)) - to.col(i), threshold)) out.push_back(static_cast<int>(i));
  }
  return out;
}

// RANSAC over minimal sets (Dim points), then least squares on the inliers
// until they no longer change (at most a few rounds).
template <int Dim>
std::optional<Fit<Dim>> robust_similarity(const Points<Dim>& from,
                                          const Points<Dim>& to,
                                          double threshold,
                                          int iterations) {
  const int n = static_cast<int>(from.cols());
  if (n < Dim) return std::nullopt;
  std::mt19937 rng(7);
  std::optional<Fit<Dim>> best;
  for (int it = 0; it < iterations; ++it) {
    std::vector<int> sample(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) sample[std::size_t(i)] = i;
    std::shuffle(sample.begin(), sample.end(), rng);
    sample.resize(Dim);
    auto fit = fit_similarity<Dim>(from, to, sample);
    if (!fit) continue;
    fit->inliers = inliers_of(*fit, from, to, threshold);
    if (!best || fit->inliers.size() > best->inliers.size()) best = fit;
  }
  if (!best || static_cast<int>(best->inliers.size()) < Dim) return std::nullopt;
  for (int round = 0; round < 5; ++round) {
    auto refined = fit_similarity<Dim>(from, to, best->inliers);
    if (!refined) break;
    refined->inliers = inliers_of(*refined, from, to, threshold);
    const bool same = refined->inliers == best->inliers;
    if (static_cast<int>(refined->inliers.size()) < Dim) break;
    best = refined;
    if (same) break;
  }
  return best;
}

std::string rounded_metres(double m) {
  std::ostringstream out;
  out.precision(m < 10 ? 2 : 3);
  out << m;
  return out.str();
}

}  // namespace

std::vector<PhotoPosition> read_photo_positions(const std::filesystem::path& file) {
  const std::vector<PhotoGps> photos = read_json_report(file, [](const nlohmann::ordered_json& j) {
    const auto it = j.find("photos");  // none: e.g. the report of an sfm run on an existing model
    return it == j.end() ? std::vector<PhotoGps>{} : photo_gps_from_json(*it);
  });
  std::vector<PhotoPosition> out;
  for (const PhotoGps& photo : photos) {
    if (!photo.gps) continue;
    const GeoPosition& gps = *photo.gps;
    if (!std::isfinite(gps.latitude_deg) || !std::isfinite(gps.longitude_deg) || std::abs(gps.latitude_deg) > 90.0 ||
        std::abs(gps.longitude_deg) > 360.0) {
      throw InputError(file.string(), "photo " + photo.name + ": latitude or longitude out of range");
    }
    out.push_back({photo.name, gps});
  }
  return out;
}

namespace {

// The registered cameras' centres and the GPS positions of the same photos.
struct MatchedPositions {
  std::vector<Eigen::Vector3d> centres;
  std::vector<GeoPosition> gps;
  int altitudes = 0;  // how many of them have an altitude
};

MatchedPositions match_positions(const std::vector<CameraPose>& cameras, const std::vector<PhotoPosition>& positions) {
  std::map<std::string, GeoPosition> by_name;
  for (const PhotoPosition& p : positions) by_name[p.name] = p.gps;
  MatchedPositions m;
  for (const CameraPose& c : cameras) {
    const auto it = by_name.find(c.name);
    if (it == by_name.end()) continue;
    m.centres.push_back(c.centre);
    m.gps.push_back(it->second);
    m.altitudes += it->second.altitude_m.has_value();
  }
  return m;
}

// The local frame at the mean position (altitude: the mean of those given).
EnuFrame mean_frame(const std::vector<GeoPosition>& gps) {
  GeoPosition reference;
  double altitude_sum = 0.0;
  int altitudes = 0;
  for (const GeoPosition& g : gps) {
    reference.latitude_deg += g.latitude_deg / double(gps.size());
    reference.longitude_deg += g.longitude_deg / double(gps.size());
    if (g.altitude_m) altitude_sum += *g.altitude_m, ++altitudes;
  }
  if (altitudes > 0) reference.altitude_m = altitude_sum / altitudes;
  return EnuFrame(reference);
}

// The horizontal similarity with the vertical from up_in_model; false (and
// the reason in result) when the positions do not fix it.
bool fit_horizontal(const Points<3>& model,
                    const Points<3>& enu,
                    const std::vector<GeoPosition>& gps,
                    const Eigen::Vector3d& up_in_model,
                    const GeoAlignmentOptions& options,
                    GeoAlignment& result) {
  const Eigen::Matrix3d level =
      Eigen::Quaterniond::FromTwoVectors(up_in_model, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Points<3> levelled = level * model;
  const Points<2> from2 = levelled.topRows<2>(), to2 = enu.topRows<2>();
  const auto fit2 = robust_similarity<2>(from2, to2, options.inlier_threshold_m, options.ransac_iterations);
  if (!fit2) {
    result.reason = "the GPS positions fit no similarity of the cameras";
    return false;
  }
  result.inliers = static_cast<int>(fit2->inliers.size());
  for (std::size_t a = 0; a < fit2->inliers.size(); ++a) {
    for (std::size_t b = a + 1; b < fit2->inliers.size(); ++b) {
      result.spread_m = std::max(result.spread_m, (to2.col(fit2->inliers[a]) - to2.col(fit2->inliers[b])).norm());
    }
  }
  if (result.spread_m < options.min_spread_m) {
    result.reason =
        "GPS spread " + rounded_metres(result.spread_m) + " m < " + rounded_metres(options.min_spread_m) + " m";
    return false;
  }
  std::vector<double> heights;
  double squared = 0.0;
  for (int i : fit2->inliers) {
    squared += ((*fit2)(from2.col(i)) - to2.col(i)).squaredNorm();
    if (gps[std::size_t(i)].altitude_m) heights.push_back(enu(2, i) - fit2->scale * levelled(2, i));
  }
  result.usable = true;
  result.has_altitude = !heights.empty();
  result.rms_residual_m = std::sqrt(squared / double(fit2->inliers.size()));
  Eigen::Matrix3d rotation2 = Eigen::Matrix3d::Identity();
  rotation2.topLeftCorner<2, 2>() = fit2->rotation;
  result.enu_from_model.scale = fit2->scale;
  result.enu_from_model.rotation = rotation2 * level;
  result.enu_from_model.translation << fit2->translation, heights.empty() ? 0.0 : upper_median(heights);
  return true;
}

// The full 3D fit replaces the horizontal one when it fixes the tilt well:
// the standard error of a plane's slope, vertical residual over the
// horizontal spread of the inliers.
void fit_vertical_too(const Points<3>& model,
                      const Points<3>& enu,
                      const GeoAlignmentOptions& options,
                      GeoAlignment& result) {
  const auto fit3 = robust_similarity<3>(model, enu, options.inlier_threshold_m, options.ransac_iterations);
  if (!fit3 || fit3->inliers.size() < 3) return;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (int i : fit3->inliers) centroid += enu.col(i).head<2>();
  centroid /= double(fit3->inliers.size());
  double vertical = 0.0, radius = 0.0, residual = 0.0;
  for (int i : fit3->inliers) {
    const Eigen::Vector3d r = (*fit3)(model.col(i)) - enu.col(i);
    vertical += r.z() * r.z();
    residual += r.squaredNorm();
    radius += (enu.col(i).head<2>() - centroid).squaredNorm();
  }
  const double count = double(fit3->inliers.size());
  result.tilt_uncertainty_deg =
      std::atan(std::sqrt(vertical / count) / (std::sqrt(radius / count) * std::sqrt(count))) * 180.0 /
      std::numbers::pi;
  if (!(result.tilt_uncertainty_deg <= options.max_tilt_uncertainty_deg)) return;
  result.vertical_from_gps = true;
  result.inliers = static_cast<int>(fit3->inliers.size());
  result.rms_residual_m = std::sqrt(residual / count);
  result.enu_from_model.scale = fit3->scale;
  result.enu_from_model.rotation = fit3->rotation;
  result.enu_from_model.translation = fit3->translation;
}

}  // namespace

GeoAlignment align_to_gps(const std::vector<CameraPose>& cameras,
                          const std::vector<PhotoPosition>& positions,
                          const Eigen::Vector3d& up_in_model,
                          const GeoAlignmentOptions& options) {
  GeoAlignment result;
  const MatchedPositions matched = match_positions(cameras, positions);
  const std::vector<GeoPosition>& gps = matched.gps;
  result.photos_with_gps = static_cast<int>(gps.size());
  if (gps.empty()) {
    result.reason = "no GPS";
    return result;
  }
  if (gps.size() < 3) {
    result.reason = format_message("only ", gps.size(), " registered photos have GPS");
    return result;
  }
  result.frame = mean_frame(gps);
  const auto n = static_cast<Eigen::Index>(gps.size());
  Points<3> enu(3, n), model(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    enu.col(i) = result.frame.enu_from_geodetic(gps[std::size_t(i)]);
    model.col(i) = matched.centres[std::size_t(i)];
  }
  if (!fit_horizontal(model, enu, gps, up_in_model, options, result)) return result;
  if (matched.altitudes == static_cast<int>(gps.size())) fit_vertical_too(model, enu, options, result);
  return result;
}

}  // namespace hos::texture
