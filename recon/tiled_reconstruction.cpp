#include "recon/tiled_reconstruction.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <unordered_map>

#include "core/error.h"
#include "core/fnv1a.h"
#include "core/option_set.h"
#include "core/stopwatch.h"
#include "recon/isosurface.h"
#include "recon/memory_budget.h"
#include "recon/tile_function_file.h"
#include "recon/trim.h"

namespace hos::recon {
namespace {

constexpr float kNoValue = std::numeric_limits<float>::quiet_NaN();

std::vector<Eigen::Vector3f> points_in_core(const std::vector<Eigen::Vector3f>& points,
                                            const GridGeometry& lattice,
                                            const NodeBox& core) {
  std::vector<Eigen::Vector3f> in;
  for (const auto& p : points) {
    const Eigen::Vector3d u = lattice.to_grid(p.cast<double>());
    if ((u.array() >= core.lo.cast<double>().array()).all() && (u.array() <= core.hi.cast<double>().array()).all()) {
      in.push_back(p);
    }
  }
  return in;
}

TileFunctionHeader expected_header(const TiledRun& run, int k) {
  TileFunctionHeader h;
  h.tile = k;
  h.num_tiles = static_cast<int>(run.plan.tiles.size());
  h.fingerprint = run.fingerprint;
  h.box = run.plan.tiles[k].extended;
  return h;
}

// Calls fn(node, offset) for the nodes of box, x fastest; offset counts them.
template <typename Fn>
void for_each_node(const NodeBox& box, Fn&& fn) {
  std::int64_t at = 0;
  for (int k = box.lo.z(); k <= box.hi.z(); ++k) {
    for (int j = box.lo.y(); j <= box.hi.y(); ++j) {
      for (int i = box.lo.x(); i <= box.hi.x(); ++i) fn(Eigen::Vector3i(i, j, k), at++);
    }
  }
}

// The blended g on the nodes of box (the core grown by one), NaN where no
// tile with a positive weight has a value: sum_t w_t g_t / sum_t w_t, the
// tiles in index order (the same bits in every process).
std::vector<double> blend(const TiledRun& run,
                          const std::filesystem::path& dir,
                          const NodeBox& box,
                          Reporter& reporter) {
  const std::size_t n = static_cast<std::size_t>(box.num_nodes());
  std::vector<double> sums(n, 0.0), weights(n, 0.0);
  const Eigen::Vector3i dims = box.hi - box.lo + Eigen::Vector3i::Ones();
  for (std::size_t u = 0; u < run.plan.tiles.size(); ++u) {
    const Tile& tile = run.plan.tiles[u];
    const NodeBox part = tile.extended.intersected(box);
    if (part.empty()) continue;
    reporter.throw_if_cancelled();
    TileFunctionReader reader(tile_function_file(dir, static_cast<int>(u)), expected_header(run, static_cast<int>(u)));
    const std::vector<float> piece = reader.read(part);
    for_each_node(part, [&](const Eigen::Vector3i& node, std::int64_t at) {
      const float v = piece[at];
      const double w = blend_weight(tile, node, run.plan.options.tile_blend);
      if (std::isnan(v) || w <= 0.0) return;
      const Eigen::Vector3i local = node - box.lo;
      const std::size_t i = (std::size_t(local.z()) * dims.y() + local.y()) * dims.x() + local.x();
      sums[i] += w * v;
      weights[i] += w;
    });
  }
  for (std::size_t i = 0; i < n; ++i) sums[i] = weights[i] > 0.0 ? sums[i] / weights[i] : std::nan("");
  return sums;
}

// The core's blended values as a band on the grid of box: the core's nodes
// with a value are active, the rest of the box (one node around the core,
// where the vertex normals' differences reach) stored, so only the core's
// cells are meshed.
StoredField core_field(const GridGeometry& grid,
                       const NodeBox& box,
                       const NodeBox& core,
                       const std::vector<double>& g) {
  RowRuns active;
  active.dims = grid.dims;
  active.row_begin.assign(static_cast<std::size_t>(active.rows()) + 1, 0);
  const auto value = [&](int i, int j, int k) { return g[(std::size_t(k) * grid.dims.y() + j) * grid.dims.x() + i]; };
  const Eigen::Vector3i lo = core.lo - box.lo, hi = core.hi - box.lo;
  for (int k = 0; k < grid.dims.z(); ++k) {
    for (int j = 0; j < grid.dims.y(); ++j) {
      const std::int64_t row = std::int64_t{k} * grid.dims.y() + j;
      if (k >= lo.z() && k <= hi.z() && j >= lo.y() && j <= hi.y()) {
        for (int i = lo.x(); i <= hi.x();) {
          if (std::isnan(value(i, j, k))) {
            ++i;
            continue;
          }
          NodeRun r{i, i};
          while (r.end <= hi.x() && !std::isnan(value(r.end, j, k))) ++r.end;
          active.runs.push_back(r);
          i = r.end;
        }
      }
      active.row_begin[row + 1] = static_cast<std::int64_t>(active.runs.size());
    }
  }
  StoredField f;
  f.nodes = std::make_shared<const ActiveNodes>(ActiveNodes::from_runs(grid, std::move(active)));
  f.values.assign(static_cast<std::size_t>(f.nodes->storage_size()), 0.0);
  for (const NodeSpan& sp : f.nodes->stored_spans()) {
    for (int i = sp.begin; i < sp.end; ++i) {
      const double v = value(i, sp.j, sp.k);
      f.values[sp.first + (i - sp.begin)] = std::isnan(v) ? 0.0 : v;
    }
  }
  return f;
}

// Is the edge from node along axis in a face of core (where the next core
// meshes it too)?
bool on_core_face(const NodeBox& core, const GridEdge& e, const Eigen::Vector3i& node) {
  for (int b = 0; b < 3; ++b) {
    if (b != e.axis && (node[b] == core.lo[b] || node[b] == core.hi[b])) return true;
  }
  return false;
}

// Appends a core's mesh to mesh; vertices on the core's faces that an
// earlier core made already (the same lattice edge) are that vertex.
void weld_into(TriangleMesh& mesh,
               std::unordered_map<std::int64_t, int>& shared,
               const TriangleMesh& part,
               const std::vector<GridEdge>& edges,
               const GridGeometry& lattice,
               const NodeBox& box,
               const NodeBox& core) {
  std::vector<int> index(part.vertices.size());
  for (std::size_t v = 0; v < part.vertices.size(); ++v) {
    const GridEdge& e = edges[v];
    const Eigen::Vector3i node = e.node + box.lo;
    if (e.axis >= 0 && on_core_face(core, e, node)) {
      const std::int64_t key = lattice.index(node.x(), node.y(), node.z()) * 3 + e.axis;
      const auto [it, inserted] = shared.try_emplace(key, static_cast<int>(mesh.vertices.size()));
      index[v] = it->second;
      if (!inserted) continue;
    } else {
      index[v] = static_cast<int>(mesh.vertices.size());
    }
    mesh.vertices.push_back(part.vertices[v]);
    mesh.normals.push_back(part.normals[v]);
  }
  for (const Eigen::Vector3i& f : part.faces) mesh.faces.emplace_back(index[f[0]], index[f[1]], index[f[2]]);
}

// Adds one tile's solve figures to the run's: iterations and times summed,
// the solves and residual histories in tile order, the residual the worst
// tile's.
void add_tile_solve(const ReconStats& tile, ReconStats& run) {
  run.solver_iterations += tile.solver_iterations;
  run.seconds_field += tile.seconds_field;
  run.seconds_solve += tile.seconds_solve;
  run.solve_iterations.insert(run.solve_iterations.end(), tile.solve_iterations.begin(), tile.solve_iterations.end());
  run.residual_history.insert(run.residual_history.end(), tile.residual_history.begin(), tile.residual_history.end());
  run.relative_residual = std::max(run.relative_residual, tile.relative_residual);
}

}  // namespace

double median_gradient_magnitude(const GridGeometry& g,
                                 const StoredField& f,
                                 const std::vector<Eigen::Vector3f>& points) {
  if (points.empty()) return 1.0;
  std::vector<double> magnitudes;
  magnitudes.reserve(points.size());
  const double h = g.spacing;
  for (const auto& p : points) {
    const Eigen::Vector3d x = p.cast<double>();
    Eigen::Vector3d gradient;
    for (int a = 0; a < 3; ++a) {
      const Eigen::Vector3d e = Eigen::Vector3d::Unit(a) * h;
      gradient[a] = (sample_trilinear(g, f, x + e) - sample_trilinear(g, f, x - e)) / (2.0 * h);
    }
    magnitudes.push_back(gradient.norm());
  }
  const auto mid = magnitudes.begin() + static_cast<std::ptrdiff_t>(magnitudes.size() / 2);
  std::nth_element(magnitudes.begin(), mid, magnitudes.end());
  return *mid > 0.0 ? *mid : 1.0;
}

std::uint64_t tiled_run_fingerprint(const OrientedSamples& samples, const TilePlan& plan) {
  Fnv1a f;
  f.add(samples.points.size());
  for (const auto& p : samples.points) f.add(p);
  for (const auto& n : samples.normals) f.add(n);
  for (float w : samples.weights) f.add(w);
  f.add(samples.frame.center);
  f.add(samples.frame.scale);
  // The options as the config dump writes them; threads and the budget do
  // not change a tile's function (the budget acts through the boxes).
  ReconOptions options = plan.options;
  options.threads = 0;
  options.max_memory_mb = 0;
  OptionSet set("recon");
  register_options(set, options);
  const std::string text = set.documented_yaml();
  f.add_bytes(text.data(), text.size());
  f.add(plan.lattice.dims);
  f.add(plan.lattice.origin);
  f.add(plan.lattice.spacing);
  for (const Tile& t : plan.tiles) {
    f.add(t.core.lo);
    f.add(t.core.hi);
    f.add(t.extended.lo);
    f.add(t.extended.hi);
    f.add(t.grid.dims);
    f.add(t.grid_offset);
  }
  return f.value();
}

double voxels_to_seam(const TiledRun& run, const Eigen::Vector3f& world) {
  const Eigen::Vector3d u =
      run.plan.lattice.to_grid((world.cast<double>() - run.samples.frame.center) / run.samples.frame.scale);
  double nearest = std::numeric_limits<double>::infinity();
  for (const Tile& t : run.plan.tiles) {
    if ((u.array() < t.core.lo.cast<double>().array()).any() || (u.array() > t.core.hi.cast<double>().array()).any()) {
      continue;
    }
    for (int a = 0; a < 3; ++a) {
      if (t.neighbour_below[a]) nearest = std::min(nearest, u[a] - t.core.lo[a]);
      if (t.neighbour_above[a]) nearest = std::min(nearest, t.core.hi[a] - u[a]);
    }
  }
  return nearest;
}

TiledRun prepare_tiled_run(const PointCloud& input, const ReconOptions& options, Reporter& reporter) {
  begin_run(input, options);
  TiledRun run;
  run.samples = usable_samples(input, options, run.stats, reporter);
  const RunGrid whole = choose_run_grid(run.samples, options, /*clamp_to_budget=*/false, run.stats, reporter);
  const std::size_t budget = memory_budget_bytes(options);
  run.plan = plan_tiles(run.samples.points, whole.grid, whole.options, options.tiles, budget);
  run.fingerprint = tiled_run_fingerprint(run.samples, run.plan);
  run.stats.tiles = static_cast<int>(run.plan.tiles.size());
  return run;
}

TileSolveReport solve_tile(const TiledRun& run, int k, const std::filesystem::path& dir, Reporter& reporter) {
  const TilePlan& plan = run.plan;
  const int count = static_cast<int>(plan.tiles.size());
  if (k < 0 || k >= count) {
    throw ConfigError("--tile", format_message(k, " is not a tile of this run: the plan has ", count, " tiles (0 .. ",
                                               count - 1, ")"));
  }
  const Tile& tile = plan.tiles[k];
  const OrientedSamples samples = tile_samples(run.samples, plan, tile);
  const ReconOptions options = tile_options(plan, tile);
  TileSolveReport report;
  report.grid_nodes = tile.grid.num_nodes();
  report.num_samples = samples.points.size();
  const std::size_t budget = memory_budget_bytes(options);
  const std::size_t estimate = estimate_peak_bytes(tile.grid, samples.points, options);
  if (estimate > budget) {
    throw ConfigError("recon.tiles", format_message("tile ", k, " of ", count, " (a ", tile.grid.dims.x(), "x",
                                                    tile.grid.dims.y(), "x", tile.grid.dims.z(), " grid) needs about ",
                                                    megabytes(estimate), ", more than the budget of ",
                                                    megabytes(budget), " (recon.max_memory_mb); give more tiles"));
  }
  reporter.info(format_message("recon: tile ", k, " of ", count, ": ", samples.points.size(), " samples, grid ",
                               tile.grid.dims.x(), "x", tile.grid.dims.y(), "x", tile.grid.dims.z(), " (",
                               tile.grid.num_nodes(), " nodes), lambda ", options.lambda));
  std::vector<float> values(static_cast<std::size_t>(tile.extended.num_nodes()), kNoValue);
  if (samples.points.size() >= 4) {
    const ImplicitFunction fn = solve_implicit_function(samples, tile.grid, options, report.stats, reporter);
    // Each tile's f has its own scale and isovalue: normalised to an
    // approximate signed distance, they can be blended.
    report.isovalue = fn.isovalue;
    std::vector<Eigen::Vector3f> core_points = points_in_core(samples.points, plan.lattice, tile.core);
    report.gradient_scale =
        median_gradient_magnitude(tile.grid, fn.f, core_points.empty() ? samples.points : core_points);
    for_each_node(tile.extended, [&](const Eigen::Vector3i& node, std::int64_t at) {
      const Eigen::Vector3i n = node - tile.grid_offset;
      const std::int64_t base = fn.f.nodes->row_base(n.y(), n.z(), n.x());
      if (base == ActiveNodes::kNotStored) return;
      values[at] = static_cast<float>((fn.f.values[base + n.x()] - fn.isovalue) / report.gradient_scale);
    });
  }
  TileFunctionHeader header = expected_header(run, k);
  header.isovalue = report.isovalue;
  header.gradient_scale = report.gradient_scale;
  write_tile_function(tile_function_file(dir, k), header, values);
  return report;
}

ReconResult join_tiles(const TiledRun& run,
                       const PointCloud& input,
                       const std::filesystem::path& dir,
                       Reporter& reporter) {
  const TilePlan& plan = run.plan;
  const GridGeometry& lattice = plan.lattice;
  const int count = static_cast<int>(plan.tiles.size());
  // Every file checked before any work, so a missing one fails at once.
  for (int u = 0; u < count; ++u) TileFunctionReader(tile_function_file(dir, u), expected_header(run, u));
  ReconResult result;
  result.stats = run.stats;
  ReconStats& stats = result.stats;
  const auto t_mesh = Clock::now();
  reporter.begin("join tiles", count);
  std::unordered_map<std::int64_t, int> shared;
  for (int t = 0; t < count; ++t) {
    const NodeBox& core = plan.tiles[t].core;
    // Grown by one past the lattice too: nodes there have no value, so the
    // core's layout is never every node of its grid (which would mesh the
    // ghost ring).
    const NodeBox box = core.grown(1);
    stats.largest_join_nodes = std::max(stats.largest_join_nodes, box.num_nodes());
    GridGeometry grid = lattice;
    grid.dims = box.hi - box.lo + Eigen::Vector3i::Ones();
    grid.origin = lattice.position(box.lo.x(), box.lo.y(), box.lo.z());
    StoredField field;
    {
      const std::vector<double> g = blend(run, dir, box, reporter);
      field = core_field(grid, box, core, g);
    }
    std::vector<GridEdge> edges;
    const TriangleMesh part = extract_isosurface(grid, field, 0.0, edges);
    weld_into(result.mesh, shared, part, edges, lattice, box, core);
    reporter.advance();
  }
  reporter.end();
  stats.isovalue = 0.0;
  stats.faces_before_trim = result.mesh.faces.size();
  const ReconOptions& options = plan.options;
  if (options.trim.enabled) {
    stats.faces_trimmed = trim_far_from_samples(
        result.mesh, run.samples.points, options.trim.distance_voxels * lattice.spacing, options.trim.sparse_reach);
  } else {
    remove_unreferenced_vertices(result.mesh);
  }
  stats.seconds_mesh = seconds_since(t_mesh);
  if (result.mesh.faces.empty()) {
    throw NumericalError("recon", "the isosurface of the joined tiles is empty (the orientations may be inconsistent)");
  }
  to_world(run.samples.frame, result.mesh);
  remove_debris_and_report(options.debris, result, reporter,
                           {&input.positions, &input.confidence, options.trim.distance_voxels * stats.voxel_size});
  reporter.info(format_message("recon: joined ", count, " tiles: ", result.mesh.num_vertices(), " vertices, ",
                               result.mesh.num_faces(), " faces (", stats.faces_trimmed,
                               " trimmed); largest core with its ring ", stats.largest_join_nodes, " nodes"));
  return result;
}

ReconResult reconstruct_with_tiles(const PointCloud& input,
                                   const ReconOptions& options,
                                   const std::filesystem::path& dir,
                                   Reporter& reporter) {
  if (options.tiles == 1) return reconstruct_surface(input, options, reporter);
  const TiledRun run = prepare_tiled_run(input, options, reporter);
  const TilePlan& plan = run.plan;
  const int count = static_cast<int>(plan.tiles.size());
  if (options.tiles == 0 && count == 1) return reconstruct_surface(input, options, reporter);
  const GridGeometry& g = plan.lattice;
  reporter.info(format_message(
      "recon: the ", g.dims.x(), "x", g.dims.y(), "x", g.dims.z(), " grid in ", count, " tiles (",
      options.tiles > 0
          ? std::string("recon.tiles")
          : format_message("its estimated peak of ", megabytes(plan.whole_estimated_peak_bytes),
                           " exceeds the budget of ", megabytes(memory_budget_bytes(options)), ", recon.max_memory_mb"),
      "), overlap ", options.tile_overlap_voxels, " voxels; tile functions in ", dir.string()));
  ReconStats solved;
  std::int64_t largest_tile = 0;
  for (int k = 0; k < count; ++k) {
    reporter.throw_if_cancelled();
    const TileSolveReport r = solve_tile(run, k, dir, reporter);
    largest_tile = std::max(largest_tile, r.grid_nodes);
    add_tile_solve(r.stats, solved);
  }
  ReconResult result = join_tiles(run, input, dir, reporter);
  result.stats.largest_tile_nodes = largest_tile;
  add_tile_solve(solved, result.stats);
  return result;
}

}  // namespace hos::recon
