// A thin part through matching, fusion and recon at their defaults, with the
// true cameras: hos-synth's hanging lantern (a body 0.18 h wide on a wire
// 0.004 h and a pole 0.015 h wide, h the objects' height) in front of the
// other objects, which are its background in the views that see it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <iostream>
#include <string>
#include <vector>

#include "core/mesh_connectivity.h"
#include "core/reporter.h"
#include "core/types.h"
#include "eval/surface_distance.h"
#include "eval/visible_surface.h"
#include "mvs/run_mvs.h"
#include "recon/reconstruct.h"
#include "synth/scene.h"
#include "tests/mvs/synthetic_workspace.h"

namespace hos::mvs {
namespace {

using mvs_testing::make_synthetic_workspace;
using mvs_testing::SyntheticWorkspace;

bool inside(const BoundingBox& box, const Eigen::Vector3f& p) {
  return (p.array() >= box.min.array()).all() && (p.array() <= box.max.array()).all();
}

BoundingBox grown(BoundingBox box, float margin) {
  box.min.array() -= margin;
  box.max.array() += margin;
  return box;
}

// The faces of mesh whose corners all lie in box (or, with inverted, not all).
TriangleMesh faces_in(const TriangleMesh& mesh, const BoundingBox& box, bool inverted = false) {
  TriangleMesh part;
  part.vertices = mesh.vertices;
  for (const Eigen::Vector3i& f : mesh.faces) {
    const bool in =
        inside(box, mesh.vertices[f[0]]) && inside(box, mesh.vertices[f[1]]) && inside(box, mesh.vertices[f[2]]);
    if (in != inverted) part.faces.push_back(f);
  }
  return part;
}

// The bounding box of the largest piece (by area) of mesh.
BoundingBox largest_piece_box(const TriangleMesh& mesh) {
  const MeshPieces pieces = connected_pieces(mesh);
  std::vector<double> area(pieces.count, 0.0);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Eigen::Vector3i& t = mesh.faces[f];
    const Eigen::Vector3f& a = mesh.vertices[t[0]];
    area[pieces.face_piece[f]] += 0.5 * (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a).norm();
  }
  const int largest = static_cast<int>(std::max_element(area.begin(), area.end()) - area.begin());
  BoundingBox box;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    if (pieces.face_piece[f] == largest)
      for (int c = 0; c < 3; ++c) box.extend(mesh.vertices[mesh.faces[f][c]]);
  return box;
}

// Scores at `fraction` of the scene's diagonal (compare_surfaces takes
// fractions of the truth's own diagonal): result a mesh, or points when it
// has no faces.
eval::ThresholdScore score(const TriangleMesh& result, const TriangleMesh& truth, double fraction, double diagonal) {
  eval::SurfaceDistanceOptions options;
  options.num_samples = 20000;
  options.thresholds = {fraction * diagonal / bounding_box(truth.vertices).diagonal()};
  return eval::compare_surfaces(result, truth, options, null_reporter()).scores[0];
}

// The scene's objects but the one named `except`, as one mesh.
TriangleMesh objects_but(synth::Scene scene, const std::string& except) {
  for (std::size_t i = scene.names.size(); i-- > 0;) {
    if (scene.names[i] != except) continue;
    scene.objects.erase(scene.objects.begin() + static_cast<std::ptrdiff_t>(i));
    scene.names.erase(scene.names.begin() + static_cast<std::ptrdiff_t>(i));
    scene.is_ground.erase(scene.is_ground.begin() + static_cast<std::ptrdiff_t>(i));
  }
  return synth::merged_mesh(scene, false);
}

// The vertices of the pieces of mesh that reach into box.
std::vector<Eigen::Vector3f> pieces_reaching(const TriangleMesh& mesh, const BoundingBox& box) {
  const MeshPieces pieces = connected_pieces(mesh);
  std::vector<bool> reaches(pieces.count, false);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    for (int c = 0; c < 3; ++c)
      if (inside(box, mesh.vertices[mesh.faces[f][c]])) reaches[pieces.face_piece[f]] = true;
  std::vector<Eigen::Vector3f> vertices;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    if (reaches[pieces.face_piece[f]])
      for (int c = 0; c < 3; ++c) vertices.push_back(mesh.vertices[mesh.faces[f][c]]);
  return vertices;
}

// Measured (12 views at 480x360): fused points' recall 0.899 of the body at
// 0.5% of the diagonal and 0.933 of the pole, arm and wire at 0.25% (about
// half the pole's width); the recon mesh's 0.948 of the body at 1% and 0.974
// of the thin parts at 0.5%, in a piece 0.26 units (7% of the diagonal) from
// the other objects at its nearest. Near the body the mesh lies within 2% of
// the lantern's truth over 0.995 of its area but within 1% over only 0.86:
// the grid the points' density chooses is 8.6 voxels across the body, and
// its unseen underside and the sides towards the pole bulge out (docs/
// benchmarks-mvs.md).
TEST(ThinParts, HangingLanternSurvivesMatchingFusionAndRecon) {
  synth::SceneOptions scene_options;
  scene_options.hanging_object = true;
  synth::DatasetOptions options;
  options.num_views = 12;
  options.width = 480;
  options.height = 360;
  const SyntheticWorkspace s = make_synthetic_workspace(scene_options, options);
  const auto named = std::find(s.scene.names.begin(), s.scene.names.end(), "lantern");
  ASSERT_NE(named, s.scene.names.end());
  const TriangleMesh& lantern = s.scene.objects[named - s.scene.names.begin()].mesh;

  // The lantern's surface that two views see, depth-tested against the whole
  // scene; its body (the largest piece) and its thin parts (pole, arm, wire).
  const TriangleMesh seen =
      eval::visible_part(synth::merged_mesh(s.scene, false), s.workspace.model, 2, null_reporter());
  const float margin = 1e-4f * static_cast<float>(s.diagonal);
  const BoundingBox body_box = grown(largest_piece_box(lantern), margin);
  const TriangleMesh lantern_seen = faces_in(seen, grown(bounding_box(lantern.vertices), margin));
  const TriangleMesh body_seen = faces_in(lantern_seen, body_box);
  const TriangleMesh thin_seen = faces_in(lantern_seen, body_box, true);
  ASSERT_GT(body_seen.faces.size(), 100u);
  ASSERT_GT(thin_seen.faces.size(), 100u);

  // Matching and fusion: points over the body and along the thin parts.
  const MvsResult mvs = run_mvs(s.workspace, MvsOptions{}, null_reporter());
  TriangleMesh points;
  points.vertices = mvs.points.positions;
  const double body_points = score(points, body_seen, 0.005, s.diagonal).recall;
  const double thin_points = score(points, thin_seen, 0.0025, s.diagonal).recall;

  // Recon: a surface over the body and the thin parts, in a piece of its own
  // (no blob joining it to the objects behind), near the truth.
  const recon::ReconResult recon = recon::reconstruct_surface(mvs.points, recon::ReconOptions{}, null_reporter());
  const double body_mesh = score(recon.mesh, body_seen, 0.01, s.diagonal).recall;
  const double thin_mesh = score(recon.mesh, thin_seen, 0.005, s.diagonal).recall;
  const std::vector<Eigen::Vector3f> body_piece = pieces_reaching(recon.mesh, body_box);
  ASSERT_FALSE(body_piece.empty()) << "no surface at the lantern's body";
  const std::vector<double> to_objects =
      eval::distances_to_mesh(body_piece, objects_but(s.scene, "lantern"), null_reporter());
  const double gap = *std::min_element(to_objects.begin(), to_objects.end());
  const TriangleMesh near_body = faces_in(recon.mesh, grown(body_box, 0.02f * static_cast<float>(s.diagonal)));
  const double near_body_precision = score(near_body, lantern, 0.02, s.diagonal).precision;
  std::cout << "lantern: fused points' recall " << body_points << " (body, 0.5% of the diagonal), " << thin_points
            << " (pole, arm, wire, 0.25%); recon mesh's " << body_mesh << " (body, 1%), " << thin_mesh
            << " (thin parts, 0.5%); its piece " << gap << " from the other objects; precision near the body "
            << near_body_precision << " (2%)\n";
  EXPECT_GE(body_points, 0.85);
  EXPECT_GE(thin_points, 0.85);
  EXPECT_GE(body_mesh, 0.9);
  EXPECT_GE(thin_mesh, 0.9);
  EXPECT_GT(gap, 0.02 * s.diagonal);
  EXPECT_GE(near_body_precision, 0.97);
}

}  // namespace
}  // namespace hos::mvs
