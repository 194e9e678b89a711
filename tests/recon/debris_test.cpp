// recon/debris.*: small detached pieces go, attached thin parts stay, and the
// option keeps everything; end to end, a small cluster of stray points gives
// no piece of the reconstructed surface.
#include "recon/debris.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "recon/recon_report.h"
#include "recon/reconstruct.h"
#include "synth/shapes.h"
#include "tests/recon/shape_samples.h"

namespace hos::recon {
namespace {

// b's vertices and faces appended to a.
void append(TriangleMesh& a, const TriangleMesh& b) {
  const int base = static_cast<int>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (const auto& f : b.faces) a.faces.push_back(f + Eigen::Vector3i::Constant(base));
}

// The unit sphere (area about 4 pi) and a sphere of radius 0.05 (0.25% of it)
// two units away.
TriangleMesh sphere_and_speck() {
  TriangleMesh mesh = synth::icosphere(3, 1.0f);
  append(mesh, synth::icosphere(2, 0.05f, Eigen::Vector3f(3.0f, 0.0f, 0.0f)));
  return mesh;
}

TEST(Debris, SmallDetachedPieceIsRemoved) {
  TriangleMesh mesh = sphere_and_speck();
  const std::size_t sphere_faces = synth::icosphere(3, 1.0f).faces.size();
  const DebrisReport report = remove_debris(mesh, DebrisOptions{});
  EXPECT_EQ(report.components, 2u);
  EXPECT_EQ(report.components_removed, 1u);
  EXPECT_EQ(report.faces_removed, synth::icosphere(2).faces.size());
  // The speck's area: a sphere of radius 0.05 (the icosphere's chords make it
  // a few percent smaller).
  EXPECT_NEAR(report.area_removed, 4.0 * std::numbers::pi * 0.05 * 0.05, 0.1 * 4.0 * std::numbers::pi * 0.05 * 0.05);
  EXPECT_NEAR(report.area_kept, 4.0 * std::numbers::pi, 0.1 * 4.0 * std::numbers::pi);
  EXPECT_EQ(mesh.faces.size(), sphere_faces);
  for (const auto& v : mesh.vertices) EXPECT_LT(v.norm(), 1.01f);  // only the sphere's vertices remain
  EXPECT_EQ(testing::analyze_topology(mesh).components, 1);
}

TEST(Debris, ThinPartAttachedToTheSurfaceIsKept) {
  TriangleMesh mesh = synth::icosphere(3, 1.0f);
  // A long, thin spike (area far below any fraction of the sphere's) standing
  // on one vertex of the sphere: the same piece, so it stays.
  const Eigen::Vector3f tip = 2.5f * mesh.vertices[0];
  const Eigen::Vector3f side = 0.002f * mesh.vertices[0].unitOrthogonal();
  const int base = static_cast<int>(mesh.vertices.size());
  mesh.vertices.push_back(tip + side);
  mesh.vertices.push_back(tip - side);
  mesh.faces.emplace_back(0, base, base + 1);
  const std::size_t faces = mesh.faces.size();
  const DebrisReport report = remove_debris(mesh, DebrisOptions{});
  EXPECT_EQ(report.components, 1u);
  EXPECT_EQ(report.components_removed, 0u);
  EXPECT_EQ(mesh.faces.size(), faces);
  EXPECT_EQ(mesh.vertices.size(), static_cast<std::size_t>(base + 2));
}

TEST(Debris, OptionOffKeepsEveryPieceAndCountsThem) {
  TriangleMesh mesh = sphere_and_speck();
  const TriangleMesh before = mesh;
  DebrisOptions keep;
  keep.remove = false;
  const DebrisReport report = remove_debris(mesh, keep);
  EXPECT_EQ(report.components, 2u);
  EXPECT_EQ(report.components_removed, 0u);
  EXPECT_EQ(report.faces_removed, 0u);
  EXPECT_EQ(mesh.faces, before.faces);
  EXPECT_EQ(mesh.vertices, before.vertices);
}

TEST(Debris, PiecesAtTheThresholdAreKept) {
  TriangleMesh mesh = sphere_and_speck();
  DebrisOptions options;
  // The speck is about 0.25% of the sphere: kept below that fraction.
  options.min_area_fraction = 0.002;
  EXPECT_EQ(remove_debris(mesh, options).components_removed, 0u);
  options.min_area_fraction = 0.003;
  EXPECT_EQ(remove_debris(mesh, options).components_removed, 1u);
}

// Samples on the speck of sphere_and_speck, each confirmed by `views` views.
void add_speck_samples(std::vector<Eigen::Vector3f>& points, std::vector<float>& views, int count, float confirmed) {
  const TriangleMesh speck = synth::icosphere(2, 0.05f, Eigen::Vector3f(3.0f, 0.0f, 0.0f));
  for (int i = 0; i < count; ++i) {
    points.push_back(speck.vertices[static_cast<std::size_t>(i) % speck.vertices.size()]);
    views.push_back(confirmed);
  }
}

// A small piece that many samples confirmed by several views each support
// (a hanging object whose wire left no surface) stays; the same piece made
// of points only two views agreed on, or of too few points, goes.
TEST(Debris, SmallPieceThatManyViewsConfirmedIsKept) {
  DebrisOptions options;
  options.keep_min_views = 3.5;
  const std::size_t speck_faces = synth::icosphere(2).faces.size();
  const auto run = [&](int count, float confirmed) {
    TriangleMesh mesh = sphere_and_speck();
    std::vector<Eigen::Vector3f> points;
    std::vector<float> views;
    // The sphere's own samples do not count for the speck.
    for (const auto& v : synth::icosphere(3, 1.0f).vertices) {
      points.push_back(v);
      views.push_back(9.0f);
    }
    add_speck_samples(points, views, count, confirmed);
    const std::size_t faces = mesh.faces.size();
    const DebrisReport report = remove_debris(mesh, options, {&points, &views, 0.01});
    return std::pair{faces - mesh.faces.size(), report.components_kept_by_support};
  };
  EXPECT_EQ(run(200, 5.0f), std::pair(std::size_t{0}, std::size_t{1}));
  EXPECT_EQ(run(200, 2.0f), std::pair(speck_faces, std::size_t{0}));
  EXPECT_EQ(run(20, 5.0f), std::pair(speck_faces, std::size_t{0}));
  options.keep_min_views = 0.0;  // off
  EXPECT_EQ(run(200, 5.0f), std::pair(speck_faces, std::size_t{0}));
}

// A sphere of points and a small, dense cluster of stray points beside it,
// as MVS outliers are: the cluster's closed blob is removed by default and
// kept with debris.remove off, and report.json counts it.
TEST(Debris, StrayPointClusterLeavesNoPieceInTheReconstruction) {
  PointCloud points = synth::sample_sphere(30000, 1.0, 0.002, 1);
  const PointCloud stray = synth::sample_sphere(600, 0.09, 0.002, 2);
  for (std::size_t i = 0; i < stray.positions.size(); ++i) {
    points.positions.push_back(stray.positions[i] + Eigen::Vector3f(1.6f, 0.0f, 0.0f));
    points.normals.push_back(stray.normals[i]);
  }
  ReconOptions options;
  options.resolution = 80;
  const ReconResult cleaned = reconstruct_surface(points, options, null_reporter());
  EXPECT_EQ(testing::analyze_topology(cleaned.mesh).components, 1);
  EXPECT_EQ(cleaned.stats.debris.components, 2u);
  EXPECT_EQ(cleaned.stats.debris.components_removed, 1u);
  for (const auto& v : cleaned.mesh.vertices) EXPECT_LT(v.norm(), 1.2f);
  const ReconReport report = recon_report(cleaned);
  EXPECT_EQ(report.debris_pieces_removed, 1);
  EXPECT_GT(report.debris_area_removed, 0.0);

  options.debris.remove = false;
  const ReconResult kept = reconstruct_surface(points, options, null_reporter());
  EXPECT_EQ(testing::analyze_topology(kept.mesh).components, 2);
  EXPECT_EQ(kept.stats.debris.components_removed, 0u);
}

}  // namespace
}  // namespace hos::recon
