#include "refine/photo_consistency.h"

#include <gtest/gtest.h>

#include <iostream>
#include <utility>

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

// The rock's true mesh pushed outwards by 1.5 pixels along its normals: every
// target should point back by that much. A vertex whose patch runs past the
// rock's silhouette in its reference view gets a target only from a partial
// patch.
TEST(SearchNormalOffsets, PartialPatchesReachTheSilhouettesAndPointBackToTheSurface) {
  testing::RockScene scene = testing::make_rock_scene(16, 1);
  TriangleMesh mesh = scene.truth;
  const std::vector<Eigen::Vector3f> true_normals = vertex_normals(mesh);
  const std::vector<float> footprints = pixel_footprints(mesh, true_normals, scene.views, 75.0);
  std::vector<double> finite;
  for (float f : footprints) {
    if (std::isfinite(f)) finite.push_back(f);
  }
  const double shift = 1.5 * median(finite);
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    mesh.vertices[v] += static_cast<float>(shift) * true_normals[v];
  const std::vector<Eigen::Vector3f> normals = vertex_normals(mesh);
  render_depths(mesh, scene.views, 0);
  const double tolerance = 2.0 * mean_edge_length(mesh);
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

}  // namespace
}  // namespace hos::refine
