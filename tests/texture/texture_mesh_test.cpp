// End-to-end tests of texture_mesh on analytic sphere scenes with known albedo.
#include "texture/texture_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/image_mask.h"
#include "synth/shapes.h"
#include "tests/texture/scene_fixtures.h"

namespace hos::texture {
namespace {

using testing::make_view;
using testing::render_sphere;
using testing::sample_atlas;
using testing::six_views_of_sphere;
using testing::sphere_albedo;
using testing::texture_points;
using testing::view_name;

constexpr double kRadius = 1.0;

// Views on two rings around the sphere; gains[i] multiplies view i's image.
std::vector<TextureView> ring_views(int count,
                                    const std::vector<float>& gains = {},
                                    double elevation_a = 35.0,
                                    double elevation_b = -35.0) {
  std::vector<TextureView> views;
  for (int i = 0; i < count; ++i) {
    TextureView view = make_view(view_name(i), 360.0 * i / count + 7.0, i % 2 == 0 ? elevation_a : elevation_b, 3.5);
    render_sphere(view, kRadius, gains.empty() ? 1.0f : gains[i]);
    views.push_back(std::move(view));
  }
  return views;
}

// PSNR of the texture against the true albedo, over non-flat sample points.
double texture_psnr(const TexturedMesh& mesh, float albedo_gain = 1.0f) {
  double sse = 0.0;
  std::size_t n = 0;
  for (const auto& p : texture_points(mesh)) {
    if (p.flat) continue;
    const Eigen::Vector3f truth =
        255.0f * albedo_gain * sphere_albedo(p.position.normalized() * static_cast<float>(kRadius));
    sse += (sample_atlas(mesh.atlases[p.page], p.uv) - truth).squaredNorm();
    n += 3;
  }
  return 10.0 * std::log10(255.0 * 255.0 / (sse / static_cast<double>(n)));
}

TEST(TextureMesh, TextureMatchesTrueAlbedo) {
  const TriangleMesh mesh = synth::icosphere(4, kRadius);
  const auto views = ring_views(10);
  TextureOptions options;
  options.decimation_error_px = 0.0;  // every face kept (the count is checked)
  const TextureResult result = texture_mesh(mesh, views, options, null_reporter());
  EXPECT_EQ(result.stats.faces, mesh.faces.size());
  EXPECT_EQ(result.stats.num_unseen_faces, 0);
  EXPECT_GE(result.stats.num_atlases, 1);
  const double psnr = texture_psnr(result.mesh);
  std::cout << "[ figures  ] texture PSNR vs true albedo " << psnr << " dB\n";
  // Bound: the sphere is rendered exactly and the mesh is a 5120-face chord
  // approximation; resampling and JPEG-free 8-bit rounding cost a few dB.
  EXPECT_GT(psnr, 30.0) << "PSNR " << psnr;
}

TEST(TextureMesh, SmallAtlasesSplitIntoPagesOrShrink) {
  const TriangleMesh mesh = synth::icosphere(4, kRadius);
  const auto views = ring_views(10);
  TextureOptions options;
  options.atlas_size = 256;
  const TextureResult paged = texture_mesh(mesh, views, options, null_reporter());
  EXPECT_GT(paged.stats.num_atlases, 1);
  for (const auto& page : paged.mesh.atlases) EXPECT_LE(std::max(page.cols, page.rows), 256);
  EXPECT_DOUBLE_EQ(paged.stats.texel_scale, 1.0);
  EXPECT_GT(texture_psnr(paged.mesh), 30.0);
  options.max_atlases = 1;
  const TextureResult shrunk = texture_mesh(mesh, views, options, null_reporter());
  EXPECT_EQ(shrunk.stats.num_atlases, 1);
  EXPECT_LT(shrunk.stats.texel_scale, 1.0);
  // Fewer texels blur the texture but keep it right.
  EXPECT_GT(texture_psnr(shrunk.mesh), 25.0);
}

// PSNR of the textured mesh rendered from a held-out camera (a photo not
// used for texturing) against that photo, over the pixels the mesh covers
// away from its silhouette (the mesh is a chord approximation); the whole
// image's PSNR in whole_image_psnr.
double held_out_object_psnr(const TexturedMesh& mesh, double azimuth, double elevation, double* whole_image_psnr) {
  TextureView held_out = make_view("held_out", azimuth, elevation, 3.0);
  render_sphere(held_out, kRadius);
  cv::Mat image, mask;
  testing::render_textured(mesh, held_out, image, mask);
  cv::Mat inner;
  cv::erode(mask, inner, cv::Mat::ones(5, 5, CV_8U));
  EXPECT_GT(cv::countNonZero(inner), 5000);
  if (whole_image_psnr) *whole_image_psnr = cv::PSNR(image, held_out.image, 255.0);
  cv::Mat diff;
  cv::absdiff(image, held_out.image, diff);
  diff.convertTo(diff, CV_32FC3);
  diff = diff.mul(diff);
  double sse = 0.0;
  std::size_t n = 0;
  for (int y = 0; y < inner.rows; ++y) {
    for (int x = 0; x < inner.cols; ++x) {
      if (!inner.at<std::uint8_t>(y, x)) continue;
      const cv::Vec3f d = diff.at<cv::Vec3f>(y, x);
      sse += d[0] + d[1] + d[2];
      n += 3;
    }
  }
  return 10.0 * std::log10(255.0 * 255.0 / (sse / static_cast<double>(n)));
}

constexpr std::pair<double, double> kHeldOutViews[] = {{25.0, 10.0}, {150.0, -15.0}, {260.0, 50.0}};

TEST(TextureMesh, HeldOutViewsMatchRenderedTexture) {
  const TriangleMesh mesh = synth::icosphere(4, kRadius);
  const TextureResult result = texture_mesh(mesh, ring_views(10), TextureOptions{}, null_reporter());
  for (const auto& [azimuth, elevation] : kHeldOutViews) {
    double psnr = 0.0;
    const double object_psnr = held_out_object_psnr(result.mesh, azimuth, elevation, &psnr);
    std::cout << "[ figures  ] held-out view az " << azimuth << " el " << elevation << ": PSNR over the object "
              << object_psnr << " dB (whole image " << psnr << " dB)\n";
    EXPECT_GT(object_psnr, 28.0);
  }
}

TEST(TextureMesh, DecimatesByDefaultWhereTheSurfaceMovesByAFractionOfAPixel) {
  // A sphere tessellated far finer than its photos resolve: most faces go,
  // and held-out views see nearly the same texture as on the whole mesh.
  const TriangleMesh mesh = synth::icosphere(6, kRadius);  // 81920 faces
  const auto views = ring_views(10);
  TextureOptions whole_options;
  whole_options.decimation_error_px = 0.0;
  const TextureResult whole = texture_mesh(mesh, views, whole_options, null_reporter());
  const TextureResult decimated = texture_mesh(mesh, views, TextureOptions{}, null_reporter());
  EXPECT_EQ(decimated.stats.input_faces, mesh.faces.size());
  EXPECT_LT(decimated.stats.faces, mesh.faces.size() / 2);
  for (const auto& [azimuth, elevation] : kHeldOutViews) {
    const double whole_psnr = held_out_object_psnr(whole.mesh, azimuth, elevation, nullptr);
    const double decimated_psnr = held_out_object_psnr(decimated.mesh, azimuth, elevation, nullptr);
    std::cout << "[ figures  ] " << mesh.faces.size() << " -> " << decimated.stats.faces << " faces; held-out view az "
              << azimuth << ": PSNR over the object " << whole_psnr << " -> " << decimated_psnr << " dB\n";
    // At 55 dB the whole mesh's render is exact to the photo's rounding;
    // 40 dB is an RMS error of 2.6 grey levels where the collapses moved the
    // surface (the bound, half the finest pixel in the ring's views, is
    // coarser for a held-out view from higher up).
    EXPECT_GT(decimated_psnr, 40.0);
  }
}

// Mean colour jump across seams: for every mesh edge between two triangles
// whose UVs differ (different charts), the texture sampled just inside each
// triangle near the edge midpoint.
double mean_seam_jump(const TexturedMesh& mesh) {
  struct Side {
    int page;
    Eigen::Vector2f uv;
  };
  std::map<std::pair<std::array<float, 3>, std::array<float, 3>>, std::vector<Side>> edges;
  for (std::size_t page = 0; page < mesh.indices.size(); ++page) {
    const auto& idx = mesh.indices[page];
    for (std::size_t i = 0; i + 2 < idx.size(); i += 3) {
      const std::uint32_t tri[3] = {idx[i], idx[i + 1], idx[i + 2]};
      const Eigen::Vector2f uv_centroid = (mesh.uvs[tri[0]] + mesh.uvs[tri[1]] + mesh.uvs[tri[2]]) / 3.0f;
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t a = tri[c], b = tri[(c + 1) % 3];
        std::array<float, 3> pa{mesh.positions[a].x(), mesh.positions[a].y(), mesh.positions[a].z()};
        std::array<float, 3> pb{mesh.positions[b].x(), mesh.positions[b].y(), mesh.positions[b].z()};
        if (pb < pa) std::swap(pa, pb);
        const Eigen::Vector2f mid = 0.5f * (mesh.uvs[a] + mesh.uvs[b]);
        edges[{pa, pb}].push_back({static_cast<int>(page), mid + 0.25f * (uv_centroid - mid)});
      }
    }
  }
  double sum = 0.0;
  int count = 0;
  for (const auto& [key, sides] : edges) {
    if (sides.size() != 2) continue;
    if ((sides[0].uv - sides[1].uv).norm() < 0.02f && sides[0].page == sides[1].page) continue;
    sum += (sample_atlas(mesh.atlases[sides[0].page], sides[0].uv) -
            sample_atlas(mesh.atlases[sides[1].page], sides[1].uv))
               .norm();
    ++count;
  }
  return count > 0 ? sum / count : 0.0;
}

// The mean of the values a histogram counts, each at its bin's centre.
double histogram_mean(const Histogram& h) {
  double sum = 0.0;
  for (std::size_t i = 0; i < h.counts.size(); ++i)
    sum += double(h.counts[i]) * (h.lo + (double(i) + 0.5) * h.bin_width());
  return sum / double(std::max<std::int64_t>(h.total(), 1));
}

TEST(TextureMesh, ExposureAndLevelingReduceSeamJumps) {
  const TriangleMesh mesh = synth::icosphere(4, kRadius);
  std::vector<float> gains(10, 1.0f);
  for (int i = 0; i < 10; i += 3) gains[i] = 1.3f;  // some photos 30% brighter
  const auto views = ring_views(10, gains);
  TextureOptions off;
  off.exposure_compensation = false;
  off.global_leveling = false;
  off.local_blending = false;
  const double jump_off = mean_seam_jump(texture_mesh(mesh, views, off, null_reporter()).mesh);
  TextureOptions global_only;
  global_only.local_blending = false;
  const double jump_global = mean_seam_jump(texture_mesh(mesh, views, global_only, null_reporter()).mesh);
  TextureOptions on;
  const TextureResult leveled = texture_mesh(mesh, views, on, null_reporter());
  const double jump_on = mean_seam_jump(leveled.mesh);
  std::cout << "[ figures  ] mean seam jump (8-bit RGB): none " << jump_off << ", exposure+global " << jump_global
            << ", + local blending " << jump_on << "\n";
  EXPECT_LT(jump_on, jump_global);
  // The brighter photos get a gain near 1/1.3 relative to the others.
  for (int i = 0; i < 10; ++i) {
    for (int k = 0; k < 3; ++k) {
      const float relative = leveled.stats.exposure_gains[i][k] * gains[i] / leveled.stats.exposure_gains[1][k];
      EXPECT_NEAR(relative, 1.0f, 0.05f) << "view " << i << " channel " << k;
    }
  }
  EXPECT_LT(jump_on, 0.5 * jump_off) << "off " << jump_off << " on " << jump_on;
  EXPECT_LT(jump_on, 8.0) << "off " << jump_off << " on " << jump_on;
  // The run report's figures: every face in the views-per-face histogram (a
  // ring of 10 photos sees each face from a few), every seam pair before and
  // after leveling.
  const TextureStats& s = leveled.stats;
  EXPECT_EQ(s.views_per_face.total(), std::int64_t(s.faces));
  ASSERT_GE(s.views_per_face.counts.size(), 3u);
  EXPECT_GT(s.views_per_face.total() - s.views_per_face.counts[0] - s.views_per_face.counts[1], 0)
      << "some faces are seen by two photos or more";
  EXPECT_GT(s.seam_jumps_before.total(), 0);
  EXPECT_EQ(s.seam_jumps_before.total(), s.seam_jumps_after.total());
  // Each histogram agrees with its mean to within a bin (no jump here exceeds the last bin).
  EXPECT_NEAR(histogram_mean(s.seam_jumps_before), s.mean_seam_jump_before, s.seam_jumps_before.bin_width());
  EXPECT_NEAR(histogram_mean(s.seam_jumps_after), s.mean_seam_jump_after, s.seam_jumps_after.bin_width());
  EXPECT_LT(s.mean_seam_jump_after, s.mean_seam_jump_before);
}

int count_red_samples(const TexturedMesh& mesh) {
  int red = 0;
  for (const auto& p : texture_points(mesh)) {
    const Eigen::Vector3f c = sample_atlas(mesh.atlases[p.page], p.uv);
    if (c.x() > 150.0f && c.y() < 90.0f && c.z() < 90.0f) ++red;
  }
  return red;
}

TEST(TextureMesh, OccluderInOnePhotoDoesNotReachTheTexture) {
  const TriangleMesh mesh = synth::icosphere(4, kRadius);
  auto views = ring_views(12);
  // A red ball between view 0's camera and the sphere, in that photo only
  // (a person walking through one photo): invisible to the depth test.
  testing::Occluder ball;
  ball.center = 0.45 * views[0].pose.center();
  ball.radius = 0.35;
  render_sphere(views[0], kRadius, 1.0f, ball);
  TextureOptions options;
  const TextureResult result = texture_mesh(mesh, views, options, null_reporter());
  EXPECT_GT(result.stats.num_outlier_rejections, 0);
  EXPECT_EQ(count_red_samples(result.mesh), 0);
  // Without the check the ball does appear, so the test can fail.
  options.outlier_rejection = false;
  options.smoothness = 0.0;
  options.gradient_floor = 1000.0;  // prefer the closest, most frontal view: view 0
  const TextureResult unchecked = texture_mesh(mesh, views, options, null_reporter());
  EXPECT_GT(count_red_samples(unchecked.mesh), 0);
}

// The same red ball in view 0, now masked out there (a person the user
// masked): with the checks that would catch it off and view 0 preferred, no
// red reaches the texture; without the mask it does.
TEST(TextureMesh, MaskedPixelsNeverColourTheTexture) {
  const TriangleMesh mesh = synth::icosphere(4, kRadius);
  auto views = ring_views(12);
  const cv::Mat clean = views[0].image.clone();
  testing::Occluder ball;
  ball.center = 0.45 * views[0].pose.center();
  ball.radius = 0.35;
  render_sphere(views[0], kRadius, 1.0f, ball);
  // The ball's pixels: where the photo changed (its rim included).
  cv::Mat changed;
  cv::absdiff(views[0].image, clean, changed);
  cv::cvtColor(changed, changed, cv::COLOR_BGR2GRAY);
  TextureOptions options;
  options.outlier_rejection = false;
  options.smoothness = 0.0;
  options.gradient_floor = 1000.0;  // prefer the closest, most frontal view: view 0
  ASSERT_GT(count_red_samples(texture_mesh(mesh, views, options, null_reporter()).mesh), 0);
  views[0].mask = cv::Mat(changed.size(), CV_8U, cv::Scalar(kUsable));
  views[0].mask.setTo(kMaskedOut, changed > 0);
  ASSERT_GT(count_masked(views[0].mask), 1000u);
  const TextureResult result = texture_mesh(mesh, views, options, null_reporter());
  EXPECT_EQ(count_red_samples(result.mesh), 0);
  EXPECT_EQ(result.stats.num_unseen_faces, 0);  // the other photos see behind the ball
}

TEST(TextureMesh, UnseenFacesTakeNeighbourColours) {
  const TriangleMesh mesh = synth::icosphere(3, kRadius);
  // All cameras high above: the bottom of the sphere is seen by none.
  const TextureResult result = texture_mesh(mesh, six_views_of_sphere(55.0), TextureOptions{}, null_reporter());
  ASSERT_GT(result.stats.num_unseen_faces, 0);
  int flat = 0;
  for (const auto& p : texture_points(result.mesh)) {
    if (!p.flat) continue;
    ++flat;
    const Eigen::Vector3f c = sample_atlas(result.mesh.atlases[p.page], p.uv);
    // The albedo is at least 0.2 (51) in every channel: never near black.
    EXPECT_GT(c.minCoeff(), 40.0f);
  }
  EXPECT_EQ(flat, 4 * result.stats.num_unseen_faces);
}

TEST(TextureMesh, BadMeshOrNoViewsThrowHosErrors) {
  TriangleMesh mesh = synth::icosphere(1, kRadius);
  const auto views = ring_views(3);
  EXPECT_THROW(texture_mesh(mesh, std::vector<TextureView>{}, TextureOptions{}, null_reporter()), StageError);
  mesh.faces[3][1] = 1000;
  EXPECT_THROW(texture_mesh(mesh, views, TextureOptions{}, null_reporter()), StageError);
  mesh = synth::icosphere(1, kRadius);
  mesh.vertices[2].x() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(texture_mesh(mesh, views, TextureOptions{}, null_reporter()), NumericalError);
  TextureOptions bad;
  bad.atlas_size = 10;
  EXPECT_THROW(texture_mesh(synth::icosphere(1, kRadius), views, bad, null_reporter()), ConfigError);
}

TEST(TextureMesh, RootMatrixStandsTheModelUpright) {
  const TriangleMesh mesh = synth::icosphere(2, kRadius);
  const auto views = ring_views(6);
  TextureOptions options;
  const TextureResult placed = texture_mesh(mesh, views, options, null_reporter());
  const Eigen::Matrix4d& m = placed.mesh.root_matrix;
  EXPECT_EQ(placed.placement.up.method, UpMethod::kGravity);
  // The ring's cameras have world +z up; the sphere's bottom is at z = -1.
  const Eigen::Vector3d up = (m.topLeftCorner<3, 3>() * Eigen::Vector3d::UnitZ()).normalized();
  EXPECT_GT(up.y(), std::cos(1.0 * 3.14159265358979 / 180.0));
  const Eigen::Vector4d bottom = m * Eigen::Vector4d(0, 0, -kRadius, 1);
  EXPECT_NEAR(bottom.y(), 0.0, 0.02 * kRadius);
  EXPECT_NEAR(Eigen::Vector2d(bottom.x(), bottom.z()).norm(), 0.0, 0.02 * kRadius);
  EXPECT_EQ(placed.mesh.root_matrix, placed.placement.root_matrix);
  options.up_axis = "none";
  EXPECT_TRUE(texture_mesh(mesh, views, options, null_reporter()).mesh.root_matrix.isIdentity());
}

}  // namespace
}  // namespace hos::texture
