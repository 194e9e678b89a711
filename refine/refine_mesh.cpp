#include "refine/refine_mesh.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "core/error.h"
#include "refine/edge_split.h"
#include "refine/mesh_geometry.h"
#include "refine/photo_consistency.h"
#include "refine/regularizer.h"
#include "refine/search_subset.h"

namespace hos::refine {
namespace {

constexpr int kFoldHalvings = 6;  // a flipping face's vertices try 1/2, 1/4, ... of their step

// Mean best score of the searched vertices with a target, and the fraction
// of all vertices with one (searched or filled in).
std::pair<double, double> score_summary(const std::vector<VertexTarget>& targets, const std::vector<int>& searched) {
  double sum = 0.0;
  std::size_t scored = 0;
  for (int v : searched) {
    if (targets[v].weight > 0.0f) sum += targets[v].score, ++scored;
  }
  const auto targeted =
      std::count_if(targets.begin(), targets.end(), [](const VertexTarget& t) { return t.weight > 0.0f; });
  return {scored ? sum / scored : 0.0, targets.empty() ? 0.0 : static_cast<double>(targeted) / targets.size()};
}

double largest_offset(const std::vector<VertexTarget>& targets) {
  double m = 0.0;
  for (const VertexTarget& t : targets) m = std::max(m, static_cast<double>(std::abs(t.offset)));
  return m;
}

// Moves every vertex by s along its normal; where a face would turn over
// (its normal against the old one), the steps of its vertices are halved
// until none does, so a round adds no fold-overs. Returns how many vertices
// had their step shortened.
int move_without_folds(TriangleMesh& mesh, const std::vector<Eigen::Vector3f>& normals, std::vector<float> s) {
  const std::vector<Eigen::Vector3f> before = face_area_normals(mesh);
  const std::vector<Eigen::Vector3f> start = mesh.vertices;
  std::vector<char> shortened(mesh.vertices.size(), 0);
  for (int attempt = 0; attempt <= kFoldHalvings; ++attempt) {
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) mesh.vertices[v] = start[v] + s[v] * normals[v];
    const std::vector<Eigen::Vector3f> after = face_area_normals(mesh);
    bool any = false;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      if (after[f].dot(before[f]) > 0.0f || before[f].squaredNorm() == 0.0f) continue;
      any = true;
      for (int c = 0; c < 3; ++c) {
        const int v = mesh.faces[f][c];
        s[v] = attempt == kFoldHalvings - 1 ? 0.0f : 0.5f * s[v];
        shortened[v] = 1;
      }
    }
    if (!any) break;
  }
  return static_cast<int>(std::count(shortened.begin(), shortened.end(), 1));
}

// Splits the mesh's edges until they are at most options.edge_pixels pixels
// of `level` long (in the view that resolves them finest), within the face
// budget. Each pass halves the edges at most.
void subdivide_to_footprint(TriangleMesh& mesh,
                            const std::vector<RefineView>& views,
                            int level,
                            const RefineOptions& options,
                            RefineStats& stats) {
  constexpr int kMaxPasses = 4;
  if (options.edge_pixels <= 0.0) return;
  // A split adds faces: at the budget none can be made.
  if (mesh.faces.size() >= static_cast<std::size_t>(options.max_faces)) {
    stats.face_budget_reached = true;
    return;
  }
  for (int pass = 0; pass < kMaxPasses; ++pass) {
    std::vector<float> limit = pixel_footprints(mesh, vertex_normals(mesh), views, options.max_incidence_deg);
    const float pixels = static_cast<float>(options.edge_pixels * static_cast<double>(1 << level));
    for (float& l : limit) l *= pixels;
    EdgeSplitResult split = split_long_edges(mesh, limit, static_cast<std::size_t>(options.max_faces));
    stats.split_edges += split.split_edges;
    stats.face_budget_reached = stats.face_budget_reached || split.budget_reached;
    if (split.split_edges == 0) return;
    mesh = std::move(split.mesh);
  }
}

// What the rounds on one mesh connectivity share; rebuilt when splitting
// changes the faces.
struct Connectivity {
  VertexRings rings;
  DisplacementSolver solver;

  Connectivity(const TriangleMesh& mesh, const RefineOptions& options)
      : rings(vertex_rings(mesh)), solver(rings, options) {}
};

// The vertices a level's rounds search: about options.search_spacing
// (finest level) or options.coarse_search_spacing (coarser levels) pixels of
// the level apart in the view that resolves them finest.
std::vector<int> vertices_to_search(const TriangleMesh& mesh,
                                    const VertexRings& rings,
                                    const std::vector<RefineView>& views,
                                    int level,
                                    const RefineOptions& options) {
  std::vector<float> radius = pixel_footprints(mesh, vertex_normals(mesh), views, options.max_incidence_deg);
  const double spacing = level > 0 ? options.coarse_search_spacing : options.search_spacing;
  const float pixels = static_cast<float>(spacing * static_cast<double>(1 << level));
  for (float& r : radius) r = std::isfinite(r) ? r * pixels : 0.0f;
  return spaced_vertices(mesh, rings, radius);
}

// The pyramid levels worth matching at: at most options.levels, and none
// whose largest photo is smaller than options.min_level_size on its longest
// side (coarser levels moved the surface away from the truth on 640x480
// photos, docs/refine.md). Level 0 is always used.
int usable_levels(const std::vector<RefineView>& views, const RefineOptions& options) {
  int longest = 0;
  for (const RefineView& view : views) longest = std::max({longest, view.camera.width, view.camera.height});
  int levels = 1;
  while (levels < options.levels && (longest >> levels) >= options.min_level_size) ++levels;
  return views.empty() ? 1 : std::min<int>(levels, static_cast<int>(views[0].pyramid.size()));
}

}  // namespace

RefineResult refine_mesh(const TriangleMesh& input,
                         std::vector<RefineView> views,
                         const RefineOptions& options,
                         Reporter& reporter) {
  options.validate();
  if (options.threads > 0) omp_set_num_threads(options.threads);
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  RefineResult result;
  result.mesh = input;
  TriangleMesh& mesh = result.mesh;
  RefineStats& stats = result.stats;
  const int levels = usable_levels(views, options);
  // Coarse to fine: the coarse level's wider steps catch larger errors, the
  // fine level's narrow ones place the surface to a fraction of a pixel.
  std::optional<Connectivity> connectivity;
  for (int level = levels - 1; level >= 0 && !stats.out_of_time; --level) {
    const int split_before = stats.split_edges;
    subdivide_to_footprint(mesh, views, level, options, stats);
    if (!connectivity || stats.split_edges != split_before) connectivity.emplace(mesh, options);
    const VertexRings& rings = connectivity->rings;
    const double edge = mean_edge_length(mesh);
    const std::vector<int> searched = vertices_to_search(mesh, rings, views, level, options);
    std::vector<char> is_searched(mesh.vertices.size(), 0);
    for (int v : searched) is_searched[v] = 1;
    double previous_score = -2.0;
    const int rounds = level > 0 ? options.iterations : std::max(options.iterations, options.min_rounds - stats.rounds);
    for (int round = 0; round < rounds; ++round) {
      if (elapsed() > options.max_seconds) {
        stats.out_of_time = true;
        break;
      }
      reporter.throw_if_cancelled();
      // Step 1: visibility and normals of the current surface.
      const std::vector<Eigen::Vector3f> normals = vertex_normals(mesh);
      render_depths(mesh, views, level);
      // Step 2: photometric targets along the normals, searched at some
      // vertices and filled in at the others.
      std::vector<VertexTarget> targets =
          search_normal_offsets(mesh, normals, searched, views, level, 2.0 * edge, options, reporter);
      fill_targets(rings, is_searched, targets);
      const auto [score, fraction] = score_summary(targets, searched);
      stats.round_scores.push_back(score);
      stats.round_levels.push_back(level);
      stats.round_searched.push_back(static_cast<double>(searched.size()) / mesh.vertices.size());
      stats.targeted_fraction = fraction;
      // Step 3: the regularised displacements, applied without fold-overs.
      SolveStats solve;
      const std::vector<float> s = connectivity->solver.solve(mesh, normals, targets, largest_offset(targets), &solve);
      stats.folds_prevented += move_without_folds(mesh, normals, s);
      ++stats.rounds;
      reporter.info(format_message("refine level ", level, " round ", round + 1, ": mean ZNCC ", score, " (",
                                   searched.size(), " of ", mesh.vertices.size(), " vertices searched), targets on ",
                                   100.0 * fraction, "% of the vertices, ", solve.iterations, " CG iterations, ",
                                   elapsed(), " s"));
      // The energy stalls: the next level (or the end).
      if (score - previous_score < options.min_improvement) break;
      previous_score = score;
    }
  }
  // Splitting appends vertices, so the input's keep their indices.
  double moved = 0.0;
  for (std::size_t v = 0; v < input.vertices.size(); ++v) moved += (mesh.vertices[v] - input.vertices[v]).norm();
  stats.mean_displacement = input.vertices.empty() ? 0.0 : moved / input.vertices.size();
  if (!mesh.normals.empty()) mesh.normals = vertex_normals(mesh);
  stats.seconds = elapsed();
  return result;
}

RefineResult refine_mesh(const TriangleMesh& mesh,
                         const std::string& mesh_source,
                         const UndistortedWorkspace& workspace,
                         const RefineOptions& options,
                         Reporter& reporter) {
  options.validate();
  if (mesh.faces.empty()) throw InputError(mesh_source, "the mesh has no faces");
  return refine_mesh(mesh, load_views(workspace, options.levels, reporter), options, reporter);
}

}  // namespace hos::refine
