#include "recon/reconstruct.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "core/error.h"
#include "recon/active_nodes.h"
#include "recon/energy_operator.h"
#include "recon/grid_transfer.h"
#include "recon/isosurface.h"
#include "recon/memory_budget.h"
#include "recon/multigrid.h"
#include "recon/sample_frame.h"
#include "recon/trim.h"
#include "recon/vector_field.h"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace hos::recon {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// The reference length that makes lambda resolution independent (see ReconOptions).
double reference_length(const GridGeometry& g) { return g.spacing * static_cast<double>(g.dims.maxCoeff() + 1) / 50.0; }

// Per-node IRLS weights 1 / sqrt(|grad f|^2 + eps^2) of the TV energy (2).
std::vector<double> tv_weights(const ScalarGrid& f, double eps) {
  const GridGeometry& g = f.geometry;
  std::vector<double> w(g.num_nodes());
  const double inv2h = 1.0 / (2.0 * g.spacing);
#pragma omp parallel for collapse(2) schedule(static)
  for (int k = 0; k < g.dims.z(); ++k) {
    for (int j = 0; j < g.dims.y(); ++j) {
      for (int i = 0; i < g.dims.x(); ++i) {
        const double gx = (f.at(i + 1, j, k) - f.at(i - 1, j, k)) * inv2h;
        const double gy = (f.at(i, j + 1, k) - f.at(i, j - 1, k)) * inv2h;
        const double gz = (f.at(i, j, k + 1) - f.at(i, j, k - 1)) * inv2h;
        w[g.index(i, j, k)] = 1.0 / std::sqrt(gx * gx + gy * gy + gz * gz + eps * eps);
      }
    }
  }
  return w;
}

// Eq. 12: the mean of f at the samples, by trilinear interpolation.
double mean_at_samples(const ScalarGrid& f, const std::vector<Eigen::Vector3f>& points) {
  double sum = 0.0;
  for (const auto& p : points) sum += f.sample(p.cast<double>());
  return sum / static_cast<double>(points.size());
}

// x, given on g coarsened `levels` times, prolongated to g.
void prolongate_levels(const GridGeometry& g, int levels, std::vector<double>& x) {
  for (int l = levels; l > 0; --l) {
    GridGeometry fine = g;
    for (int c = 1; c < l; ++c) fine = fine.coarsened();
    std::vector<double> finer;
    assign_large(finer, fine.num_nodes());
    prolongate_add(fine.coarsened(), x, fine, finer);
    x = std::move(finer);
  }
}

// The isovalue (eq. 12) of the unscreened solution, estimated on the grid
// coarsened up to twice. guess receives that coarse solution prolongated to
// the grid coarsened guess_level times (a starting point for the solve
// there); guess_level is lowered when the grid coarsens fewer times.
double coarse_isovalue(const EnergyOperator& fine,
                       const std::vector<double>& rhs,
                       const std::vector<Eigen::Vector3f>& points,
                       const SolverOptions& solver,
                       Reporter& reporter,
                       int& guess_level,
                       std::vector<double>& guess) {
  std::vector<EnergyOperator> ops{fine};
  std::vector<double> coarse_rhs;
  while (ops.size() < 3 && ops.back().geometry().can_coarsen(3)) {
    ops.push_back(ops.back().coarsened());
    std::vector<double> rc;
    restrict_to_coarse(ops[ops.size() - 2].geometry(), ops.size() == 2 ? rhs : coarse_rhs, ops.back().geometry(), rc);
    coarse_rhs = std::move(rc);
  }
  if (ops.size() == 1) coarse_rhs = rhs;
  std::vector<double> x;
  SolverOptions so = solver;
  so.tolerance = std::max(solver.tolerance, 1e-4);
  const SolveReport report = solve_linear_system(ops.back(), coarse_rhs, x, so, reporter);
  reporter.debug(format_message("recon: coarse unscreened solve, ", report.iterations, " CG iterations, ",
                                report.seconds_setup + report.seconds_iterations, " s"));
  ScalarGrid coarse(ops.back().geometry());
  coarse.values = x;
  const double iso = mean_at_samples(coarse, points);
  const int coarsest = static_cast<int>(ops.size()) - 1;
  guess_level = std::min(guess_level, coarsest);
  prolongate_levels(ops[guess_level].geometry(), coarsest - guess_level, x);
  guess = std::move(x);
  return iso;
}

// The band around the samples on grid g, or null when it would not leave out
// most of the grid (or g cannot hold the coarser levels a band needs).
std::shared_ptr<const ActiveNodes> worthwhile_band(const GridGeometry& g,
                                                   const std::vector<Eigen::Vector3f>& points,
                                                   int voxels) {
  if (voxels <= 0 || !g.can_coarsen(3)) return nullptr;
  auto band = std::make_shared<const ActiveNodes>(band_around_samples(g, points, voxels));
  if (2 * band->count() > g.num_nodes()) return nullptr;
  return band;
}

// Solves op x = rhs, with x given on the grid coarsened x_level times. Where
// the band around the samples is much smaller than the grid, the grid twice
// as coarse is solved first (the same way, recursively, down to the level x
// is given on), then only the band, with the nodes outside it held at the
// coarse solution's prolongation. Otherwise x is prolongated and the whole
// grid solved. solve(op, b, x) runs one linear solve. Returns the number of
// nodes of this level's band (0: none).
template <typename SolveFn>
std::int64_t solve_with_bands(EnergyOperator& op,
                              std::vector<double> rhs,
                              const std::vector<Eigen::Vector3f>& points,
                              int band_voxels,
                              int x_level,
                              std::vector<double>& x,
                              Reporter& reporter,
                              SolveFn&& solve) {
  const GridGeometry& g = op.geometry();
  const auto t_band = Clock::now();
  const std::shared_ptr<const ActiveNodes> band = x_level > 0 ? worthwhile_band(g, points, band_voxels) : nullptr;
  reporter.debug(format_message("recon: band construction ", seconds_since(t_band), " s"));
  if (!band) {
    prolongate_levels(g, x_level, x);
    solve(op, rhs, x);
    return 0;
  }
  reporter.info(format_message("recon: band of ", band->count(), " nodes (", 100.0 * band->count() / g.num_nodes(),
                               "% of the ", g.dims.x(), "x", g.dims.y(), "x", g.dims.z(), " grid)"));
  // The band's right-hand side in its compact layout, then the grid-sized one
  // is freed before any solver array exists (the peak memory).
  std::vector<double> band_rhs(band->storage_size()), band_x(band->storage_size());
  band->gather(rhs.data(), band_rhs.data());
  {
    EnergyOperator coarse = op.coarsened();
    std::vector<double> coarse_rhs;
    restrict_to_coarse(g, rhs, coarse.geometry(), coarse_rhs);
    rhs = std::vector<double>{};
    solve_with_bands(coarse, std::move(coarse_rhs), points, band_voxels, x_level - 1, x, reporter, solve);
  }
  // The band's unknowns; its halo holds the coarse solution, fixed. The
  // grid-sized solution is made after the band's solver arrays are freed.
  auto t_transfer = Clock::now();
  prolongate_add_to_stored(g.coarsened(), x, *band, band_x.data());
  op.set_active(band);
  reporter.debug(format_message("recon: band start ", seconds_since(t_transfer), " s"));
  solve(op, band_rhs, band_x);
  band_rhs = std::vector<double>{};
  t_transfer = Clock::now();
  prolongate_levels(g, 1, x);
  band->scatter_active(band_x.data(), x.data());
  reporter.debug(format_message("recon: band result to the grid ", seconds_since(t_transfer), " s"));
  return band->count();
}

// Unit orientations (weighted by confidence) in the unit frame, so that every
// step after is independent of the input's units and position; dropped
// points are counted and reported.
OrientedSamples usable_samples(const PointCloud& input,
                               const ReconOptions& options,
                               ReconStats& stats,
                               Reporter& reporter) {
  OrientedSamples samples = prepare_samples(input, options.use_confidence, "input points");
  stats.num_samples_dropped = samples.dropped_without_normal + samples.dropped_far;
  if (samples.dropped_without_normal > 0) {
    reporter.warn(
        format_message("recon: ", samples.dropped_without_normal, " points without a usable normal were ignored"));
  }
  if (samples.dropped_far > 0) {
    reporter.warn(format_message("recon: ", samples.dropped_far,
                                 " far outlier points (more than the object's extent away from it) were ignored"));
  }
  stats.num_samples = samples.points.size();
  return samples;
}

// The right-hand side of A f = -div F for the orientation field F (sec. 4.1).
ScalarGrid orientation_rhs(const GridGeometry& grid, const OrientedSamples& samples, const ReconOptions& options) {
  if (options.uniform_flux) {
    return density_scaled_rhs(grid, samples.points, samples.normals, samples.weights, options.filter_passes,
                              options.direction_filter_passes, options.filter_passes);
  }
  VectorGrid field = splat_normals(grid, samples.points, samples.normals, samples.weights);
  box_filter(field, options.filter_passes);
  normalize_field(field, samples.points, options.filter_passes);
  ScalarGrid rhs = divergence(field);
  for (double& v : rhs.values) v = -v;
  return rhs;
}

// One linear solve, its figures added to stats and reported.
void solve_and_report(const EnergyOperator& op,
                      const std::vector<double>& b,
                      std::vector<double>& x,
                      const SolverOptions& so,
                      ReconStats& stats,
                      Reporter& reporter) {
  const SolveReport report = solve_linear_system(op, b, x, so, reporter);
  stats.solver_iterations += report.iterations;
  stats.multigrid_levels = report.levels;
  stats.relative_residual = report.relative_residual;
  stats.residual_history.insert(stats.residual_history.end(), report.residual_history.begin(),
                                report.residual_history.end());
  reporter.info(format_message("recon: ", report.iterations, " CG iterations, ", report.levels,
                               " multigrid levels, relative residual ", report.relative_residual));
  reporter.debug(
      format_message("recon: solver setup ", report.seconds_setup, " s, iterations ", report.seconds_iterations, " s"));
  if (!report.converged) {
    reporter.warn(format_message("recon: the solver stopped at relative residual ", report.relative_residual,
                                 " above the tolerance ", so.tolerance, "; raise recon.solver.max_iterations"));
  }
}

// Energy (2): iteratively reweighted least squares; each round minimises the
// quadratic majoriser |grad f|^2 / (2 |grad f_old|) of the TV term exactly.
void solve_total_variation(const GridGeometry& grid,
                           const std::vector<double>& rhs,
                           const ReconOptions& options,
                           ScalarGrid& f,
                           ReconStats& stats,
                           Reporter& reporter) {
  const SolverOptions& solver = options.solver;
  solve_and_report(EnergyOperator(grid, SmoothnessEnergy::kTotalVariation, 0.0), rhs, f.values, solver, stats,
                   reporter);
  const double eps = 0.01 / ((1.0 + options.filter_passes) * grid.spacing);
  for (int round = 0; round < solver.tv_iterations; ++round) {
    reporter.throw_if_cancelled();
    SolverOptions so = solver;
    if (round + 1 < solver.tv_iterations) so.tolerance = std::max(solver.tolerance, 1e-3);
    const EnergyOperator op(grid, SmoothnessEnergy::kTotalVariation, 0.0, tv_weights(f, eps),
                            options.lambda * reference_length(grid));
    solve_and_report(op, rhs, f.values, so, stats, reporter);
  }
}

// Adds the screening term to op and its target to rhs. The target of the
// pinning is the isovalue (eq. 12) of the unscreened solution, estimated on a
// grid coarsened up to x_level times, whose prolongation (in x) also starts
// the solve.
void add_screening(EnergyOperator& op,
                   std::vector<double>& rhs,
                   const std::vector<Eigen::Vector3f>& points,
                   const ReconOptions& options,
                   int& x_level,
                   std::vector<double>& x,
                   Reporter& reporter) {
  const GridGeometry& grid = op.geometry();
  const double target = coarse_isovalue(op, rhs, points, options.solver, reporter, x_level, x);
  const auto t_screening = Clock::now();
  op.set_screening(std::make_shared<const std::vector<Eigen::Vector3f>>(points), 1.0);
  // Weighted so that at a typical surface node the term is screening
  // times the Laplacian's scale 1 / h^2, at any resolution and density.
  op.scale_screening(options.screening /
                     (grid.spacing * grid.spacing * std::max(op.screening().mean_row_sum(), 1e-12)));
  op.screening().add_target(target, rhs);
  reporter.debug(format_message("recon: screening term ", seconds_since(t_screening), " s"));
}

// Energies (1), (3), (4): one solve (screened when options.screening > 0),
// restricted to a band around the samples where that pays.
void solve_quadratic(const GridGeometry& grid,
                     std::vector<double> rhs,
                     const std::vector<Eigen::Vector3f>& points,
                     const ReconOptions& options,
                     ScalarGrid& f,
                     ReconStats& stats,
                     Reporter& reporter) {
  const SolverOptions& solver = options.solver;
  const double ell = reference_length(grid);
  const double weight = options.energy == SmoothnessEnergy::kMembrane ? options.lambda : options.lambda * ell * ell;
  EnergyOperator op(grid, options.energy, weight);
  // The solve starts on the grid coarsened twice (see solve_with_bands).
  int x_level = solver.band_voxels > 0 ? 2 : 0;
  if (options.screening > 0.0) {
    add_screening(op, rhs, points, options, x_level, f.values, reporter);
  } else {
    // From zero, on the coarsest grid the solve may start on.
    GridGeometry start = grid;
    int levels = 0;
    for (; levels < x_level && start.can_coarsen(3); ++levels) start = start.coarsened();
    x_level = levels;
    f.values.assign(start.num_nodes(), 0.0);
  }
  stats.band_nodes =
      solve_with_bands(op, std::move(rhs), points, solver.band_voxels, x_level, f.values, reporter,
                       [&](const EnergyOperator& o, const std::vector<double>& b, std::vector<double>& x) {
                         solve_and_report(o, b, x, solver, stats, reporter);
                       });
}

// Isovalue: mean of f at the samples (eq. 12), then the isosurface (sec. 4.4),
// trimmed away from the samples.
void extract_surface(const ScalarGrid& f,
                     const std::vector<Eigen::Vector3f>& points,
                     const ReconOptions& options,
                     ReconResult& result) {
  ReconStats& stats = result.stats;
  stats.isovalue = mean_at_samples(f, points);
  result.mesh = extract_isosurface(f, stats.isovalue);
  stats.faces_before_trim = result.mesh.faces.size();
  if (options.trim.enabled) {
    const TrimReport trim = trim_far_from_samples(
        result.mesh, points, options.trim.distance_voxels * f.geometry.spacing, options.trim.min_component_fraction);
    stats.faces_trimmed = trim.faces_removed_far + trim.faces_removed_small;
  }
}

}  // namespace

void check_reconstructable(const PointCloud& points, const std::string& source) {
  points.check_consistent();
  if (points.size() < 4) {
    throw InputError(source, "has " + std::to_string(points.size()) + " points; a surface needs at least 4");
  }
  if (!points.has_normals()) {
    throw InputError(source,
                     "the points have no normals (nx ny nz); give --view-dir, --scanner-pos or "
                     "--scans to orient them");
  }
  BoundingBox box;
  for (const auto& p : points.positions) {
    if (p.allFinite()) box.extend(p);
  }
  check_extent(box, source);
  for (const auto& n : points.normals) {
    if (n.allFinite() && n.squaredNorm() > 0.0f) return;
  }
  throw InputError(source, "every normal is zero or not finite: the points carry no orientation");
}

GridGeometry make_domain(const BoundingBox& box, const ReconOptions& options, int levels) {
  const Eigen::Vector3d extent = box.extent().cast<double>();
  const double longest = extent.maxCoeff();
  const Eigen::Vector3d side = extent.array() + 2.0 * options.margin * longest;
  GridGeometry g;
  g.spacing = options.voxel_size > 0.0 ? options.voxel_size : side.maxCoeff() / options.resolution;
  for (int a = 0; a < 3; ++a) {
    // At least a few nodes across every axis, also for flat point sets; at
    // most kMaxDomainNodes, counted in double so that a tiny voxel size
    // cannot overflow (the memory check then refuses such a grid).
    const double wanted = std::ceil(side[a] / g.spacing) + 1.0;
    const int nodes = static_cast<int>(
        std::clamp(std::isfinite(wanted) ? wanted : kMaxDomainNodes, 8.0, static_cast<double>(kMaxDomainNodes)));
    g.dims[a] = admissible_dims(nodes, levels);
  }
  g.origin = box.center().cast<double>() - 0.5 * g.spacing * (g.dims.cast<double>().array() - 1.0).matrix();
  return g;
}

ReconResult reconstruct_surface(const PointCloud& input, const ReconOptions& options, Reporter& reporter) {
  options.validate();
  check_reconstructable(input, "input points");
#ifdef _OPENMP
  if (options.threads > 0) omp_set_num_threads(options.threads);
#endif
  ReconResult result;
  ReconStats& stats = result.stats;
  const OrientedSamples samples = usable_samples(input, options, stats, reporter);
  const std::vector<Eigen::Vector3f>& points = samples.points;
  ReconOptions unit_options = options;
  unit_options.voxel_size = options.voxel_size / samples.frame.scale;

  const auto t_field = Clock::now();
  reporter.begin("orientation field", 0);
  const BoundingBox box = bounding_box(points);
  check_memory_budget(box, points, unit_options);  // before anything grid-sized exists
  const GridGeometry grid = make_domain(box, unit_options);
  stats.grid_dims = grid.dims;
  stats.voxel_size = grid.spacing * samples.frame.scale;
  reporter.info(format_message("recon: grid ", grid.dims.x(), "x", grid.dims.y(), "x", grid.dims.z(), ", voxel ",
                               grid.spacing, ", ", points.size(), " samples"));
  ScalarGrid rhs = orientation_rhs(grid, samples, options);
  reporter.end();
  stats.seconds_field = seconds_since(t_field);

  // Energy minimisation (sec. 3.4, 4.2, 4.3).
  const auto t_solve = Clock::now();
  reporter.begin("solve", 0);
  ScalarGrid& f = result.function;
  f.geometry = grid;  // values: the solves below size them (no grid-sized fill here)
  if (options.energy == SmoothnessEnergy::kTotalVariation) {
    solve_total_variation(grid, rhs.values, options, f, stats, reporter);
  } else {
    solve_quadratic(grid, std::move(rhs.values), points, options, f, stats, reporter);
  }
  for (double v : f.values) {
    if (!std::isfinite(v)) throw NumericalError("recon", "the implicit function is not finite");
  }
  reporter.end();
  stats.seconds_solve = seconds_since(t_solve);

  const auto t_mesh = Clock::now();
  reporter.begin("isosurface", 0);
  extract_surface(f, points, options, result);
  reporter.end();
  stats.seconds_mesh = seconds_since(t_mesh);
  if (result.mesh.faces.empty()) {
    throw NumericalError("recon", "the isosurface is empty (the orientations may be inconsistent)");
  }
  to_world(samples.frame, result.mesh);
  f.geometry.origin = samples.frame.to_world(f.geometry.origin);
  f.geometry.spacing *= samples.frame.scale;
  reporter.info(format_message("recon: isovalue ", stats.isovalue, ", ", result.mesh.num_vertices(), " vertices, ",
                               result.mesh.num_faces(), " faces (", stats.faces_trimmed, " trimmed)"));
  return result;
}

}  // namespace hos::recon
