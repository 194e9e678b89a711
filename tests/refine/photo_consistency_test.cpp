#include "refine/photo_consistency.h"

#include <gtest/gtest.h>

#include <iostream>
#include <utility>

#include "core/image_mask.h"
#include "eval/surface_distance.h"
#include "refine/mesh_geometry.h"
#include "tests/refine/rock_fixture.h"

namespace hos::refine {
namespace {

// ZNCC must not see a photo's exposure (gain and offset), and must refuse flat patches.
TEST(Zncc, IgnoresGainAndOffsetAndRefusesFlatPatches) {
  std::vector<float> a, brighter, reversed, flat(9, 0.5f);
  for (int i = 0; i < 9; ++i) {
    a.push_back(0.1f * static_cast<float>((i * 7) % 9));
    brighter.push_back(1.3f * a.back() + 0.05f);
    reversed.push_back(1.0f - a.back());
  }
  EXPECT_NEAR(*zncc(a, brighter, 0.01f), 1.0f, 1e-5f);
  EXPECT_NEAR(*zncc(a, reversed, 0.01f), -1.0f, 1e-5f);
  EXPECT_FALSE(zncc(a, flat, 0.01f).has_value());
}

double median(std::vector<double> values) { return eval::summarize_distances(std::move(values)).median; }

// The rock's true mesh pushed outwards by 1.5 pixels (the median footprint)
// along its normals, with its depth in every view: every target should point
// back by `shift`.
struct PushedRock {
  testing::RockScene scene;
  TriangleMesh mesh;
  std::vector<Eigen::Vector3f> normals;
  double shift = 0.0;
  double tolerance = 0.0;  // visibility, as refine_mesh sets it
};

PushedRock pushed_rock() {
  PushedRock rock;
  rock.scene = testing::make_rock_scene(16, 1);
  rock.mesh = rock.scene.truth;
  const std::vector<Eigen::Vector3f> true_normals = vertex_normals(rock.mesh);
  const std::vector<float> footprints = pixel_footprints(rock.mesh, true_normals, rock.scene.views, 75.0);
  std::vector<double> finite;
  for (float f : footprints) {
    if (std::isfinite(f)) finite.push_back(f);
  }
  rock.shift = 1.5 * median(finite);
  for (std::size_t v = 0; v < rock.mesh.vertices.size(); ++v)
    rock.mesh.vertices[v] += static_cast<float>(rock.shift) * true_normals[v];
  rock.normals = vertex_normals(rock.mesh);
  render_depths(rock.mesh, rock.scene.views, 0);
  rock.tolerance = 2.0 * mean_edge_length(rock.mesh);
  return rock;
}

// A vertex whose patch runs past the rock's silhouette in its reference view
// gets a target only from a partial patch.
TEST(SearchNormalOffsets, PartialPatchesReachTheSilhouettesAndPointBackToTheSurface) {
  PushedRock rock = pushed_rock();
  const auto& [scene, mesh, normals, shift, tolerance] = rock;
  RefineOptions whole, partial;
  whole.min_patch_coverage = 1.0;
  partial.min_patch_coverage = 0.6;
  const auto with_whole = search_normal_offsets(mesh, normals, scene.views, 0, tolerance, whole, null_reporter());
  const auto with_partial = search_normal_offsets(mesh, normals, scene.views, 0, tolerance, partial, null_reporter());
  std::vector<double> whole_errors, partial_errors, added_errors;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const double partial_error = std::abs(with_partial[v].offset + shift) / shift;
    if (with_whole[v].weight > 0) whole_errors.push_back(std::abs(with_whole[v].offset + shift) / shift);
    if (with_partial[v].weight > 0) partial_errors.push_back(partial_error);
    if (with_partial[v].weight > 0 && !(with_whole[v].weight > 0)) added_errors.push_back(partial_error);
  }
  std::cout << "[ figures  ] vertices with a target: " << whole_errors.size() << " whole patches, "
            << partial_errors.size() << " partial, of " << mesh.vertices.size()
            << "; median error / shift: " << median(whole_errors) << ", " << median(partial_errors)
            << ", the added ones " << median(added_errors) << "\n";
  // The silhouettes' vertices are few here (about 0.5%); their targets are
  // less sure than the rest's but must still bring them nearer the truth.
  EXPECT_GT(partial_errors.size(), whole_errors.size() + mesh.vertices.size() / 400);
  EXPECT_LT(median(whole_errors), 0.25);
  EXPECT_LT(median(partial_errors), 0.25);
  EXPECT_LT(median(added_errors), 0.8);
}

// The pushed rock, scored where even the most frontal view sees the surface
// obliquely (more than 45 degrees off its normal). Moving the patch's samples
// along the normal would slide them across the reference's texture there (by
// about the shift times the tangent of the incidence); on the reference's
// rays they stay on the texture they were sampled from.
TEST(SearchNormalOffsets, ObliqueReferencesStillPointBackToTheSurface) {
  PushedRock rock = pushed_rock();
  const auto& [scene, mesh, normals, shift, tolerance] = rock;
  RefineOptions whole_patches;
  whole_patches.min_patch_coverage = 1.0;  // the silhouettes' vertices are another test's
  const auto targets = search_normal_offsets(mesh, normals, scene.views, 0, tolerance, whole_patches, null_reporter());
  std::vector<double> oblique_errors, frontal_errors;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!(targets[v].weight > 0)) continue;
    const Eigen::Vector3d x = mesh.vertices[v].cast<double>(), n = normals[v].cast<double>();
    double most_frontal = -1.0;
    for (const RefineView& view : scene.views) {
      if (sees(view, x, tolerance)) most_frontal = std::max(most_frontal, n.dot((view.center - x).normalized()));
    }
    const double error = std::abs(targets[v].offset + shift) / shift;
    (most_frontal < std::cos(45.0 * M_PI / 180.0) ? oblique_errors : frontal_errors).push_back(error);
  }
  std::cout << "[ figures  ] median error / shift: " << median(frontal_errors) << " over " << frontal_errors.size()
            << " vertices seen within 45 degrees of head-on, " << median(oblique_errors) << " over "
            << oblique_errors.size() << " seen more obliquely\n";
  // Samples moved along the normal instead: 0.42 oblique, 0.12 frontal.
  ASSERT_GT(oblique_errors.size(), 100u);
  EXPECT_LT(median(oblique_errors), 0.2);
  EXPECT_LT(median(frontal_errors), 0.1);
}

// The upper 180 rows masked in every photo (as over a passer-by):
// the vertices that every view sees only inside it get no target, and the
// others still point back to the surface.
TEST(SearchNormalOffsets, MaskedPixelsAreNeverCompared) {
  PushedRock rock = pushed_rock();
  const testing::RockScene& scene = rock.scene;
  const TriangleMesh& mesh = rock.mesh;
  const double shift = rock.shift, tolerance = rock.tolerance;
  const int band_top = 0, band_bottom = 180;
  std::vector<RefineView> masked_views;
  for (const RefineView& view : scene.views) {
    cv::Mat grey, mask(view.pyramid[0].size(), CV_8U, cv::Scalar(kUsable));
    view.pyramid[0].convertTo(grey, CV_8U, 1.0 / 257.0);
    mask.rowRange(band_top, band_bottom).setTo(kMaskedOut);
    masked_views.push_back(make_view(view.camera, view.pose, grey, 1, view.pose.name, mask));
  }
  render_depths(mesh, masked_views, 0);
  // Projects 10 pixels or more inside the band in every view that sees it
  // (farther than the patch's half-width of 4 samples and the mask's growth).
  const auto deep_in_band = [&](const Eigen::Vector3d& x) {
    int seen = 0;
    for (const RefineView& view : scene.views) {
      if (!sees(view, x, tolerance)) continue;
      ++seen;
      const double y = view.project(x, 0)->y();
      if (y < band_top + 10 || y > band_bottom - 10) return false;
    }
    return seen > 0;
  };
  RefineOptions options;
  const auto plain = search_normal_offsets(mesh, rock.normals, scene.views, 0, tolerance, options, null_reporter());
  const auto masked = search_normal_offsets(mesh, rock.normals, masked_views, 0, tolerance, options, null_reporter());
  int in_band = 0, plain_targets_in_band = 0, masked_targets_in_band = 0;
  std::vector<double> errors_outside;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (deep_in_band(mesh.vertices[v].cast<double>())) {
      ++in_band;
      plain_targets_in_band += plain[v].weight > 0;
      masked_targets_in_band += masked[v].weight > 0;
    } else if (masked[v].weight > 0) {
      errors_outside.push_back(std::abs(masked[v].offset + shift) / shift);
    }
  }
  std::cout << "[ figures  ] " << in_band << " vertices seen only inside the band: " << plain_targets_in_band
            << " targets unmasked, " << masked_targets_in_band << " masked; " << errors_outside.size()
            << " targets outside it, median error / shift " << median(errors_outside) << "\n";
  ASSERT_GT(plain_targets_in_band, 50);
  EXPECT_EQ(masked_targets_in_band, 0);
  ASSERT_GT(errors_outside.size(), 100u);
  EXPECT_LT(median(errors_outside), 0.25);
}

}  // namespace
}  // namespace hos::refine
