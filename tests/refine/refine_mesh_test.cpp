// Refinement against ground truth: the rock of hos-synth, its true mesh
// smoothed (bumps gone, shrunk) as a too-smooth reconstruction would be, is
// refined from 16 photos and must come back towards the true surface.
#include "refine/refine_mesh.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <vector>

#include "core/error.h"
#include "eval/mesh_sanity.h"
#include "eval/self_intersection.h"
#include "eval/surface_distance.h"
#include "refine/mesh_geometry.h"
#include "tests/refine/rock_fixture.h"

namespace hos::refine {
namespace {

eval::SurfaceComparison compare(const TriangleMesh& mesh, const TriangleMesh& truth) {
  eval::SurfaceDistanceOptions options;
  options.num_samples = 30000;
  options.thresholds = {0.0025, 0.005, 0.01};
  return eval::compare_surfaces(mesh, truth, options, null_reporter());
}

// Faces whose normal turned against the true mesh's (same topology).
// Faces turned towards the centre of a star-shaped closed mesh (folded over:
// the rock is star-shaped around its centroid, checked on the truth). This
// holds for any face list, so it also covers the refinement's split faces.
int inward_faces(const TriangleMesh& mesh, const Eigen::Vector3f& centre) {
  const std::vector<Eigen::Vector3f> normals = face_area_normals(mesh);
  int inward = 0;
  for (std::size_t f = 0; f < normals.size(); ++f) {
    const Eigen::Vector3i& face = mesh.faces[f];
    const Eigen::Vector3f centroid = (mesh.vertices[face[0]] + mesh.vertices[face[1]] + mesh.vertices[face[2]]) / 3.0f;
    inward += normals[f].dot(centroid - centre) <= 0.0f;
  }
  return inward;
}

TEST(RefineMesh, SmoothedRockComesBackTowardsTheTruth) {
  RefineOptions options;
  // The smoothing moved the surface by pixels of these 400x300 photos: the
  // coarse levels (200 and 100 px) are what brings it back.
  options.min_level_size = 100;
  testing::RockScene scene = testing::make_rock_scene(16, options.levels);
  const TriangleMesh input = testing::smoothed(scene.truth, 40);
  const RefineResult result = refine_mesh(input, std::move(scene.views), options, null_reporter());
  const eval::SurfaceComparison before = compare(input, scene.truth), after = compare(result.mesh, scene.truth);
  std::cout << "[ figures  ] F at 0.5%: " << before.primary().f_score << " -> " << after.primary().f_score
            << ", F at 0.25%: " << before.scores[0].f_score << " -> " << after.scores[0].f_score << ", Chamfer "
            << before.chamfer << " -> " << after.chamfer << " (diagonal " << after.truth_diagonal << "), "
            << result.stats.rounds << " rounds, " << result.stats.seconds << " s, mean ZNCC by round";
  for (double score : result.stats.round_scores) std::cout << " " << score;
  std::cout << "\n";
  EXPECT_GT(after.primary().f_score, before.primary().f_score + 0.1);
  // Coarse to fine, every level used (and within a level, if it runs more
  // than one round, the photos agree better round by round).
  const RefineStats& stats = result.stats;
  ASSERT_EQ(stats.round_levels.size(), stats.round_scores.size());
  EXPECT_EQ(stats.round_levels.front(), options.levels - 1);
  EXPECT_EQ(stats.round_levels.back(), 0);
  for (std::size_t r = 1; r < stats.round_levels.size(); ++r) {
    EXPECT_LE(stats.round_levels[r], stats.round_levels[r - 1]);
    if (stats.round_levels[r] == stats.round_levels[r - 1]) {
      EXPECT_GT(stats.round_scores[r], stats.round_scores[r - 1]) << "round " << r;
    }
  }
  EXPECT_LT(after.chamfer, 0.6 * before.chamfer);
  // The topology is the input's, so the mesh stays closed and manifold; and no face turned over.
  const eval::MeshSanity sanity = eval::check_mesh_sanity(result.mesh);
  EXPECT_TRUE(sanity.watertight && sanity.vertex_manifold && sanity.consistently_oriented);
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  for (const Eigen::Vector3f& v : scene.truth.vertices) centre += v;
  centre /= static_cast<float>(scene.truth.vertices.size());
  ASSERT_EQ(inward_faces(scene.truth, centre), 0) << "the rock is no longer star-shaped: the check needs another";
  EXPECT_GT(result.mesh.faces.size(), input.faces.size()) << "no edge was split";
  EXPECT_EQ(inward_faces(result.mesh, centre), 0);
  ASSERT_EQ(eval::count_self_intersections(input), 0u);
  EXPECT_EQ(eval::count_self_intersections(result.mesh), 0u);
  // The smoothing shrank the rock; the photos give the volume back.
  const double truth_volume = testing::enclosed_volume(scene.truth);
  const double volume_before = testing::enclosed_volume(input) / truth_volume;
  const double volume_after = testing::enclosed_volume(result.mesh) / truth_volume;
  std::cout << "[ figures  ] volume / true volume " << volume_before << " -> " << volume_after << "\n";
  EXPECT_LT(std::abs(volume_after - 1.0), 0.5 * std::abs(volume_before - 1.0));
}

// The default searches vertices a few pixels apart at the coarser levels
// and every vertex at the finest, filling in the rest: as close to the
// truth as searching every vertex at every level, from fewer searches.
TEST(RefineMesh, SpacedSearchAtTheCoarseLevelsComesAsCloseToTheTruthAsSearchingEveryVertex) {
  RefineOptions every, spaced;
  every.min_level_size = spaced.min_level_size = 100;
  every.search_spacing = every.coarse_search_spacing = 0.0;
  ASSERT_EQ(spaced.search_spacing, 0.0);
  ASSERT_GT(spaced.coarse_search_spacing, 0.0);
  testing::RockScene scene = testing::make_rock_scene(16, every.levels);
  const TriangleMesh input = testing::smoothed(scene.truth, 40);
  const RefineResult with_every = refine_mesh(input, scene.views, every, null_reporter());
  const RefineResult with_spaced = refine_mesh(input, scene.views, spaced, null_reporter());
  const eval::SurfaceComparison a = compare(with_every.mesh, scene.truth), b = compare(with_spaced.mesh, scene.truth);
  std::cout << "[ figures  ] every vertex / spaced: F at 0.5% " << a.primary().f_score << " / " << b.primary().f_score
            << ", Chamfer " << a.chamfer << " / " << b.chamfer << ", " << with_every.stats.seconds << " / "
            << with_spaced.stats.seconds << " s, searched by round";
  for (double f : with_spaced.stats.round_searched) std::cout << " " << f;
  std::cout << "\n";
  for (double f : with_every.stats.round_searched) EXPECT_EQ(f, 1.0);
  // The coarsest level searches a small part of the vertices, the finest
  // level (its last round) all of them.
  ASSERT_GT(with_spaced.stats.round_searched.size(), 2u);
  EXPECT_LT(with_spaced.stats.round_searched.front(), 0.4);
  EXPECT_EQ(with_spaced.stats.round_searched.back(), 1.0);
  EXPECT_GT(b.primary().f_score, a.primary().f_score - 0.02);
  EXPECT_LT(b.chamfer, 1.1 * a.chamfer);
}

// One round per level, and the finest level makes up min_rounds in all: with
// three levels the coarser two supply the first rounds; with one level (small
// photos) it runs both, and the second agrees better with the photos.
TEST(RefineMesh, OneRoundPerLevelAndTheFinestMakesUpTheMinimumRounds) {
  RefineOptions three_levels, one_level;
  three_levels.min_level_size = 100;
  one_level.levels = 1;
  ASSERT_EQ(three_levels.iterations, 1);
  ASSERT_EQ(three_levels.min_rounds, 2);
  testing::RockScene scene = testing::make_rock_scene(16, three_levels.levels);
  const TriangleMesh input = testing::smoothed(scene.truth, 40);
  const RefineStats three = refine_mesh(input, scene.views, three_levels, null_reporter()).stats;
  const RefineStats one = refine_mesh(input, scene.views, one_level, null_reporter()).stats;
  EXPECT_EQ(three.round_levels, (std::vector<int>{2, 1, 0}));
  EXPECT_EQ(one.round_levels, (std::vector<int>{0, 0}));
  ASSERT_EQ(one.round_scores.size(), 2u);
  EXPECT_GT(one.round_scores[1], one.round_scores[0]);
}

TEST(RefineMesh, MeshWithoutFacesIsBadInputNamingTheFile) {
  TriangleMesh points;
  points.vertices = {Eigen::Vector3f::Zero(), Eigen::Vector3f::UnitX(), Eigen::Vector3f::UnitY()};
  try {
    refine_mesh(points, "empty.ply", UndistortedWorkspace{}, RefineOptions{}, null_reporter());
    FAIL() << "a mesh without faces was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "empty.ply");
  }
}

// Mean angle (degrees) between the faces' normals and the normal of the
// nearest true vertex, over the faces within `radius` of a crease vertex.
double crease_normal_error(const TriangleMesh& mesh,
                           const TriangleMesh& truth,
                           const std::vector<char>& crease,
                           float radius) {
  const std::vector<Eigen::Vector3f> normals = face_area_normals(mesh);
  double sum = 0.0;
  int count = 0;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Eigen::Vector3i& face = mesh.faces[f];
    const Eigen::Vector3f c = (mesh.vertices[face[0]] + mesh.vertices[face[1]] + mesh.vertices[face[2]]) / 3.0f;
    int nearest = 0;
    float nearest_d2 = std::numeric_limits<float>::max(), crease_d2 = std::numeric_limits<float>::max();
    for (std::size_t v = 0; v < truth.vertices.size(); ++v) {
      const float d2 = (truth.vertices[v] - c).squaredNorm();
      if (d2 < nearest_d2) nearest_d2 = d2, nearest = static_cast<int>(v);
      if (crease[v]) crease_d2 = std::min(crease_d2, d2);
    }
    if (crease_d2 > radius * radius || normals[f].squaredNorm() == 0.0f) continue;
    const double cosine = std::clamp(normals[f].normalized().dot(truth.normals[nearest].normalized()), -1.0f, 1.0f);
    sum += std::acos(cosine) * 180.0 / M_PI;
    ++count;
  }
  return count ? sum / count : 0.0;
}

// The crease test: hos-synth's box (rounded edges of radius 0.07 on
// a 0.64 x 0.56 x 0.52 box) from 16 photos of 400x300.
TEST(RefineMesh, BoxCreasesGetSharperAndItsVolumeStays) {
  RefineOptions options;
  options.min_level_size = 100;
  testing::RockScene scene = testing::make_object_scene("box", 16, options.levels);
  const TriangleMesh& truth = scene.truth;
  ASSERT_EQ(truth.normals.size(), truth.vertices.size());
  // Crease vertices: a neighbour's normal more than 10 degrees away (the
  // rounded edges; the box's faces are flat).
  const VertexRings rings = vertex_rings(truth);
  std::vector<char> crease(truth.vertices.size(), 0);
  for (std::size_t v = 0; v < truth.vertices.size(); ++v) {
    for (int k = rings.offsets[v]; k < rings.offsets[v + 1]; ++k) {
      crease[v] |= truth.normals[v].normalized().dot(truth.normals[rings.neighbors[k]].normalized()) <
                   std::cos(10.0 * M_PI / 180.0);
    }
  }
  const float near_creases = 2.0f * static_cast<float>(mean_edge_length(truth));
  const double true_volume = testing::enclosed_volume(truth);
  // The box smoothed (its edges rounder, 3% of the volume lost), and the
  // true box itself, each refined from the same photos.
  for (const int rounds : {10, 0}) {
    SCOPED_TRACE(rounds == 0 ? "the true box" : "the smoothed box");
    const TriangleMesh input = testing::smoothed(truth, rounds);
    const RefineResult result = refine_mesh(input, scene.views, options, null_reporter());
    const double before = crease_normal_error(input, truth, crease, near_creases);
    const double after = crease_normal_error(result.mesh, truth, crease, near_creases);
    const double volume_before = testing::enclosed_volume(input) / true_volume;
    const double volume_after = testing::enclosed_volume(result.mesh) / true_volume;
    std::cout << "[ figures  ] " << rounds << " smoothing rounds: normal error near the creases " << before << " -> "
              << after << " degrees, volume " << volume_before << " -> " << volume_after << " of the truth\n";
    if (rounds > 0) {
      EXPECT_LT(after, 0.9 * before);
      EXPECT_LT(std::abs(volume_after - 1.0), 0.5 * std::abs(volume_before - 1.0));
    } else {
      EXPECT_LE(after, before);
      EXPECT_NEAR(volume_after, 1.0, 0.005);
    }
  }
}

}  // namespace
}  // namespace hos::refine
