#include "eval/alignment.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/nearest_rotation.h"

namespace hos::eval {
namespace {

double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  if (v.size() % 2 == 1) return v[mid];
  const double upper = v[mid];
  return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + mid));
}

}  // namespace

Eigen::Matrix4d Similarity3::matrix() const {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = scale * R;
  m.topRightCorner<3, 1>() = t;
  return m;
}

Similarity3 Similarity3::inverse() const {
  Similarity3 inv;
  inv.scale = 1.0 / scale;
  inv.R = R.transpose();
  inv.t = -inv.scale * (inv.R * t);
  return inv;
}

Similarity3 umeyama(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst) {
  if (src.size() != dst.size()) throw NumericalError("eval", "umeyama: point lists differ in length");
  if (src.size() < 3) throw NumericalError("eval", "umeyama: at least 3 point pairs are needed");
  const double n = static_cast<double>(src.size());
  Eigen::Vector3d mu_src = Eigen::Vector3d::Zero(), mu_dst = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < src.size(); ++i) {
    mu_src += src[i];
    mu_dst += dst[i];
  }
  mu_src /= n;
  mu_dst /= n;
  double var_src = 0.0;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();  // Sigma_xy of Eq. 38
  for (std::size_t i = 0; i < src.size(); ++i) {
    const Eigen::Vector3d a = src[i] - mu_src, b = dst[i] - mu_dst;
    var_src += a.squaredNorm();
    cov += b * a.transpose();
  }
  var_src /= n;
  cov /= n;
  if (!(var_src > 1e-300) || !cov.allFinite()) {
    throw NumericalError("eval", "umeyama: source points are all the same (or not finite)");
  }
  Similarity3 s;
  s.R = nearest_rotation(cov);                          // Eqs. 39-40 and 43
  s.scale = (s.R.transpose() * cov).trace() / var_src;  // Eq. 42: trace(D S) = trace(R^T Sigma_xy)
  s.t = mu_dst - s.scale * (s.R * mu_src);              // Eq. 41
  if (!(s.scale > 0.0) || !std::isfinite(s.scale)) {
    throw NumericalError("eval", "umeyama: degenerate configuration (collinear points?)");
  }
  return s;
}

ModelAlignment align_models_by_image_name(const SparseModel& recovered, const SparseModel& truth) {
  std::vector<std::pair<std::string, std::pair<Eigen::Vector3d, Eigen::Vector3d>>> pairs;
  for (const auto& [id, image] : recovered.images) {
    if (const ImageRecord* t = truth.find_image(image.name)) {
      pairs.push_back({image.name, {image.center(), t->center()}});
    }
  }
  if (pairs.size() < 3) {
    throw NumericalError("eval", "alignment: only " + std::to_string(pairs.size()) +
                                     " image names are common to both models (3 needed)");
  }
  std::sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Eigen::Vector3d> src, dst;
  ModelAlignment out;
  for (const auto& [name, centres] : pairs) {
    out.names.push_back(name);
    src.push_back(centres.first);
    dst.push_back(centres.second);
  }
  out.truth_from_recovered = umeyama(src, dst);
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < src.size(); ++i) {
    const double r = (out.truth_from_recovered.apply(src[i]) - dst[i]).norm();
    out.residuals.push_back(r);
    sum_sq += r * r;
  }
  out.rms_residual = std::sqrt(sum_sq / static_cast<double>(src.size()));
  return out;
}

CameraPoseComparison compare_camera_poses(const SparseModel& recovered, const SparseModel& truth) {
  const ModelAlignment alignment = align_models_by_image_name(recovered, truth);
  CameraPoseComparison out;
  out.truth_from_recovered = alignment.truth_from_recovered;
  out.num_recovered = static_cast<int>(recovered.images.size());
  out.num_truth = static_cast<int>(truth.images.size());
  BoundingBox box;
  for (const auto& [id, image] : truth.images) box.extend(image.center().cast<float>());
  out.scene_size = box.diagonal();
  if (!(out.scene_size > 0.0)) throw NumericalError("eval", "true camera centres all coincide");
  std::vector<double> centre_errors, rotation_errors;
  for (std::size_t i = 0; i < alignment.names.size(); ++i) {
    const ImageRecord& rec = *recovered.find_image(alignment.names[i]);
    const ImageRecord& tru = *truth.find_image(alignment.names[i]);
    // cam_from_truth = cam_from_recovered * recovered_from_truth (rotation part R^T).
    const Eigen::Matrix3d aligned = rec.rotation() * alignment.truth_from_recovered.R.transpose();
    const Eigen::Matrix3d delta = tru.rotation() * aligned.transpose();
    // Angle from the quaternion: acos of the trace loses digits near zero.
    const Eigen::Quaterniond q(delta);
    CameraPoseError e;
    e.name = alignment.names[i];
    e.center_error = alignment.residuals[i] / out.scene_size;
    e.rotation_error_deg = 2.0 * std::atan2(q.vec().norm(), std::abs(q.w())) * 180.0 / M_PI;
    centre_errors.push_back(e.center_error);
    rotation_errors.push_back(e.rotation_error_deg);
    out.cameras.push_back(e);
  }
  auto summarize = [](const std::vector<double>& v, double& mean, double& median, double& max) {
    double sum = 0.0;
    for (double x : v) sum += x;
    mean = sum / static_cast<double>(v.size());
    median = median_of(v);
    max = *std::max_element(v.begin(), v.end());
  };
  summarize(centre_errors, out.mean_center_error, out.median_center_error, out.max_center_error);
  summarize(rotation_errors, out.mean_rotation_error_deg, out.median_rotation_error_deg, out.max_rotation_error_deg);
  return out;
}

void transform_mesh(TriangleMesh& mesh, const Similarity3& s) {
  for (auto& v : mesh.vertices) v = s.apply(v.cast<double>()).cast<float>();
  const Eigen::Matrix3f R = s.R.cast<float>();
  for (auto& n : mesh.normals) n = R * n;
}

void transform_points(PointCloud& cloud, const Similarity3& s) {
  for (auto& v : cloud.positions) v = s.apply(v.cast<double>()).cast<float>();
  const Eigen::Matrix3f R = s.R.cast<float>();
  for (auto& n : cloud.normals) n = R * n;
}

}  // namespace hos::eval
