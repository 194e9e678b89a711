#include "eval/alignment.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "core/error.h"
#include "tests/support/camera_poses.h"

namespace hos::eval {
namespace {

Similarity3 known_similarity() {
  Similarity3 s;
  s.scale = 2.5;
  s.R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  s.t = Eigen::Vector3d(3.0, -1.0, 0.25);
  return s;
}

// Truth: cameras on a ring around the origin looking inwards; recovered: the
// same cameras in a frame related by `truth_from_recovered`.
void make_models(const Similarity3& truth_from_recovered, double noise, SparseModel& recovered, SparseModel& truth) {
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss(0.0, noise);
  const Similarity3 inv = truth_from_recovered.inverse();
  for (int i = 0; i < 24; ++i) {
    const double a = 2.0 * M_PI * i / 24.0;
    const Eigen::Vector3d centre(4.0 * std::cos(a), 4.0 * std::sin(a), 0.5 * std::sin(3 * a));
    const Eigen::Matrix3d cam_from_world = hos::testing::cam_from_world_looking(-centre, Eigen::Vector3d::UnitZ());
    ImageRecord t;
    t.id = i + 1;
    t.name = "img" + std::to_string(i) + ".png";
    t.cam_from_world_rotation = Eigen::Quaterniond(cam_from_world);
    t.cam_from_world_translation = -cam_from_world * centre;
    truth.images[t.id] = t;

    ImageRecord r = t;
    const Eigen::Matrix3d rec_rot = cam_from_world * truth_from_recovered.R;
    const Eigen::Vector3d noisy(gauss(rng), gauss(rng), gauss(rng));
    const Eigen::Vector3d rec_centre = inv.apply(centre + noisy);
    r.cam_from_world_rotation = Eigen::Quaterniond(rec_rot);
    r.cam_from_world_translation = -rec_rot * rec_centre;
    recovered.images[r.id] = r;
  }
}

TEST(Umeyama, RecoversExactSimilarity) {
  const Similarity3 s = known_similarity();
  std::vector<Eigen::Vector3d> src, dst;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 10; ++i) {
    src.emplace_back(u(rng), u(rng), u(rng));
    dst.push_back(s.apply(src.back()));
  }
  const Similarity3 e = umeyama(src, dst);
  EXPECT_NEAR(e.scale, s.scale, 1e-10);
  EXPECT_LT((e.R - s.R).norm(), 1e-10);
  EXPECT_LT((e.t - s.t).norm(), 1e-10);
}

TEST(Umeyama, RejectsTooFewOrCoincidentPoints) {
  EXPECT_THROW(umeyama({{0, 0, 0}, {1, 0, 0}}, {{0, 0, 0}, {1, 0, 0}}), NumericalError);
  EXPECT_THROW(umeyama({{1, 1, 1}, {1, 1, 1}, {1, 1, 1}}, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}), NumericalError);
}

TEST(Umeyama, InverseComposesToIdentity) {
  const Similarity3 s = known_similarity();
  const Eigen::Vector3d x(0.3, -0.2, 5.0);
  EXPECT_LT((s.inverse().apply(s.apply(x)) - x).norm(), 1e-12);
}

TEST(AlignModels, RecoversKnownSimilarityFromNoisyCentres) {
  const Similarity3 s = known_similarity();
  SparseModel recovered, truth;
  const double noise = 0.01;  // in truth units; the ring has radius 4
  make_models(s, noise, recovered, truth);
  const ModelAlignment a = align_models_by_image_name(recovered, truth);
  ASSERT_EQ(a.names.size(), 24u);
  // With 24 centres spread over ~8 units and sigma 0.01 per axis the fit's
  // errors are ~sigma/sqrt(24)/radius: bounds are ~5x that.
  EXPECT_NEAR(a.truth_from_recovered.scale, s.scale, s.scale * 0.003);
  const Eigen::AngleAxisd dr(a.truth_from_recovered.R * s.R.transpose());
  EXPECT_LT(dr.angle(), 0.003);
  const Eigen::Vector3d probe(1, 1, 1);
  EXPECT_LT((a.truth_from_recovered.apply(probe) - s.apply(probe)).norm(), 0.02);
  EXPECT_GT(a.rms_residual, 0.3 * noise);
  EXPECT_LT(a.rms_residual, 3.0 * noise);
}

TEST(ComparePoses, ReportsPerturbedCamera) {
  const Similarity3 s = known_similarity();
  SparseModel recovered, truth;
  make_models(s, 0.0, recovered, truth);
  // Rotate one recovered camera by 2 degrees about its optical axis.
  ImageRecord& r = recovered.images.at(5);
  const Eigen::Vector3d centre = r.center();  // kept: only the orientation changes
  r.cam_from_world_rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(2.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ())) * r.cam_from_world_rotation;
  r.cam_from_world_translation = -(r.rotation() * centre);
  const CameraPoseComparison c = compare_camera_poses(recovered, truth);
  ASSERT_EQ(c.cameras.size(), 24u);
  for (const auto& e : c.cameras) {
    EXPECT_LT(e.center_error, 1e-9) << e.name;
    if (e.name == r.name) {
      EXPECT_NEAR(e.rotation_error_deg, 2.0, 1e-6);
    } else {
      EXPECT_LT(e.rotation_error_deg, 1e-6) << e.name;
    }
  }
  EXPECT_NEAR(c.max_rotation_error_deg, 2.0, 1e-6);
}

TEST(AlignModels, TooFewCommonNamesIsAnError) {
  SparseModel a, b;
  make_models(known_similarity(), 0.0, a, b);
  for (auto& [id, image] : b.images) image.name = "other_" + image.name;
  EXPECT_THROW(align_models_by_image_name(a, b), NumericalError);
}

}  // namespace
}  // namespace hos::eval
