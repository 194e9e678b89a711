#include "recon/reconstruct.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/error.h"
#include "core/huge_pages.h"
#include "core/stopwatch.h"
#include "recon/active_nodes.h"
#include "recon/energy_operator.h"
#include "recon/grid_transfer.h"
#include "recon/isosurface.h"
#include "recon/memory_budget.h"
#include "recon/multigrid.h"
#include "recon/sample_density.h"
#include "recon/sample_frame.h"
#include "recon/trim.h"
#include "recon/vector_field.h"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace hos::recon {
namespace {

// Energy (2): each reweighting round cuts its starting residual this much.
constexpr double kTotalVariationRoundReduction = 0.1;

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

// r restricted to the grid g coarsened once: on every coarse node, or, when r
// lives near the samples, on the coarse nodes its stored nodes reach.
StoredField restricted(const GridGeometry& g, const StoredField& r) {
  const GridGeometry coarse = g.coarsened();
  StoredField rc;
  rc.nodes = std::make_shared<const ActiveNodes>(
      r.nodes->is_all()
          ? ActiveNodes::all(coarse)
          : ActiveNodes::from_runs(coarse, coarse_nodes_on(dilated(r.nodes->stored_set(), 1), coarse.dims)));
  assign_large(rc.values, static_cast<std::size_t>(rc.nodes->storage_size()));
  restrict_to_coarse(g, *r.nodes, r.values.data(), coarse, *rc.nodes, rc.values.data());
  return rc;
}

// The values of f on every node of g (zero where f stores none); f's values
// are taken when it stores every node.
std::vector<double> dense_values(const GridGeometry& g, StoredField&& f) {
  if (f.nodes->is_all()) return std::move(f.values);
  std::vector<double> dense;
  assign_large(dense, g.num_nodes());
  for (const NodeSpan& sp : f.nodes->stored_spans()) {
    std::copy(f.values.begin() + sp.first, f.values.begin() + sp.first + (sp.end - sp.begin),
              dense.begin() + g.index(sp.begin, sp.j, sp.k));
  }
  return dense;
}

// The isovalue (eq. 12) of the unscreened solution, estimated on the grid
// coarsened `level` times (fewer when it does not coarsen as often; level is
// lowered to match); guess receives that coarse solution (a starting point
// for the solve there).
double coarse_isovalue(const EnergyOperator& fine,
                       const StoredField& rhs,
                       const std::vector<Eigen::Vector3f>& points,
                       const SolverOptions& solver,
                       Reporter& reporter,
                       int& level,
                       std::vector<double>& guess) {
  EnergyOperator op = fine;
  const StoredField* current = &rhs;
  StoredField r;
  int coarsened = 0;
  for (; coarsened < level && op.geometry().can_coarsen(3); ++coarsened) {
    r = restricted(op.geometry(), *current);
    current = &r;
    op = op.coarsened();
  }
  std::vector<double> coarse_rhs =
      current == &r ? dense_values(op.geometry(), std::move(r)) : dense_values(op.geometry(), StoredField(rhs));
  std::vector<double> x;
  SolverOptions so = solver;
  so.tolerance = std::max(solver.tolerance, 1e-4);
  const SolveReport report = solve_linear_system(op, std::move(coarse_rhs), x, so, reporter);
  reporter.debug(format_message("recon: coarse unscreened solve, ", report.iterations, " CG iterations, ",
                                report.seconds_setup + report.seconds_iterations, " s"));
  ScalarGrid coarse(op.geometry());
  coarse.values = x;
  level = coarsened;
  guess = std::move(x);
  return mean_at_samples(coarse, points);
}

// The band around the samples on grid g, or null when it would not leave out
// most of the grid (or g cannot hold the coarser levels a band needs). With
// band_only, any band the grid can hold.
std::shared_ptr<const ActiveNodes> band_for(const GridGeometry& g,
                                            const std::vector<Eigen::Vector3f>& points,
                                            int voxels,
                                            bool band_only) {
  if (voxels <= 0 || !g.can_coarsen(3)) return nullptr;
  auto band = std::make_shared<const ActiveNodes>(band_around_samples(g, points, voxels));
  if (!band_only && 2 * band->count() > g.num_nodes()) return nullptr;
  return band;
}

// A level's solution and the active nodes of its band (0: none).
struct LevelSolution {
  StoredField x;
  std::int64_t band_nodes = 0;
};

// Solves op x = rhs, with x given on the grid coarsened x_level times (on
// every node). Where the band around the samples is much smaller than the
// grid (or band_only), the grid twice as coarse is solved first (the same
// way, recursively, down to the level x is given on), then only the band,
// with the nodes outside it held at the coarse solution's prolongation.
// Otherwise x is prolongated and the whole grid solved. The solution is
// returned on every node, or with band_only on the band's stored nodes only
// (active: solved; halo: the coarse solution). solve(op, b, x) runs one
// linear solve and may free b (moved in).
template <typename SolveFn>
LevelSolution solve_with_bands(EnergyOperator& op,
                               StoredField rhs,
                               const std::vector<Eigen::Vector3f>& points,
                               int band_voxels,
                               bool band_only,
                               int x_level,
                               std::vector<double> x,
                               Reporter& reporter,
                               SolveFn&& solve) {
  const GridGeometry& g = op.geometry();
  const auto t_band = Clock::now();
  const std::shared_ptr<const ActiveNodes> band = x_level > 0 ? band_for(g, points, band_voxels, band_only) : nullptr;
  reporter.debug(format_message("recon: band construction ", seconds_since(t_band), " s"));
  if (!band) {
    prolongate_levels(g, x_level, x);
    solve(op, dense_values(g, std::move(rhs)), x);
    return {StoredField{std::make_shared<const ActiveNodes>(ActiveNodes::all(g)), std::move(x)}, 0};
  }
  reporter.info(format_message("recon: band of ", band->count(), " nodes (", 100.0 * band->count() / g.num_nodes(),
                               "% of the ", g.dims.x(), "x", g.dims.y(), "x", g.dims.z(), " grid), ",
                               band->storage_size(), " stored"));
  // The band's right-hand side in its compact layout, then the finer one is
  // freed before any solver array exists (the peak memory).
  std::vector<double> band_rhs(band->storage_size());
  band->gather_from(*rhs.nodes, rhs.values.data(), band_rhs.data());
  LevelSolution coarse_solution;
  {
    EnergyOperator coarse = op.coarsened();
    StoredField coarse_rhs = restricted(g, rhs);
    rhs = StoredField{};
    coarse_solution = solve_with_bands(coarse, std::move(coarse_rhs), points, band_voxels, band_only, x_level - 1,
                                       std::move(x), reporter, solve);
  }
  // The band's unknowns; its halo holds the coarse solution, fixed (the
  // coarse band's stored nodes reach every coarse node this reads). The
  // grid-sized solution is made after the band's solver arrays are freed.
  auto t_transfer = Clock::now();
  std::vector<double> band_x(band->storage_size());
  const StoredField& xc = coarse_solution.x;
  prolongate_add_to_stored(g.coarsened(), *xc.nodes, xc.values.data(), *band, band_x.data());
  // Keeping only bands, the coarse solution is not needed any more.
  if (band_only) coarse_solution = LevelSolution{};
  op.set_active(band);
  if (band_only) release_freed_memory();
  reporter.debug(format_message("recon: band start ", seconds_since(t_transfer), " s"));
  solve(op, std::move(band_rhs), band_x);
  if (band_only) return {StoredField{band, std::move(band_x)}, band->count()};
  t_transfer = Clock::now();
  std::vector<double> dense = dense_values(g.coarsened(), std::move(coarse_solution.x));
  prolongate_levels(g, 1, dense);
  band->scatter_active(band_x.data(), dense.data());
  reporter.debug(format_message("recon: band result to the grid ", seconds_since(t_transfer), " s"));
  return {StoredField{std::make_shared<const ActiveNodes>(ActiveNodes::all(g)), std::move(dense)}, band->count()};
}

// The right-hand side of A f = -div F for the orientation field F (sec. 4.1),
// on every node or, with band_only, near the samples.
StoredField orientation_rhs(const GridGeometry& grid,
                            const OrientedSamples& samples,
                            const ReconOptions& options,
                            bool band_only) {
  const FieldPasses passes{options.filter_passes, options.direction_filter_passes, options.filter_passes};
  if (band_only) return density_scaled_rhs_near_samples(grid, samples.points, samples.normals, samples.weights, passes);
  ScalarGrid rhs;
  if (options.uniform_flux) {
    rhs = density_scaled_rhs(grid, samples.points, samples.normals, samples.weights, passes);
  } else {
    VectorGrid field = splat_normals(grid, samples.points, samples.normals, samples.weights);
    box_filter(field, options.filter_passes);
    normalize_field(field, samples.points, options.filter_passes);
    rhs = divergence(field);
    for (double& v : rhs.values) v = -v;
  }
  return StoredField{std::make_shared<const ActiveNodes>(ActiveNodes::all(grid)), std::move(rhs.values)};
}

// The level the banded solve starts on (the grid coarsened that many times,
// solved whole).
int start_level(const GridGeometry& grid, const ReconOptions& options, bool band_only) {
  if (options.solver.band_voxels <= 0) return 0;
  return band_only ? band_only_start_level(grid) : 2;
}

// One linear solve (b const, or moved in to be freed early), its figures
// added to stats and reported.
template <typename B>
void solve_and_report(const EnergyOperator& op,
                      B&& b,
                      std::vector<double>& x,
                      const SolverOptions& so,
                      ReconStats& stats,
                      Reporter& reporter,
                      VectorPrecision precision = VectorPrecision::kDouble) {
  const SolveReport report = solve_linear_system(op, std::forward<B>(b), x, so, reporter, precision);
  stats.solver_iterations += report.iterations;
  stats.solve_iterations.push_back(report.iterations);
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

// ||b - A x|| / ||b||.
double relative_residual(const EnergyOperator& op, const std::vector<double>& b, const std::vector<double>& x) {
  std::vector<double> r(b.size());
  op.residual(b.data(), x.data(), r.data());
  double rr = 0.0, bb = 0.0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    rr += r[i] * r[i];
    bb += b[i] * b[i];
  }
  return bb > 0.0 ? std::sqrt(rr / bb) : 0.0;
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
    const EnergyOperator op(grid, SmoothnessEnergy::kTotalVariation, 0.0, tv_weights(f, eps),
                            options.lambda * reference_length(grid));
    // Each round's majoriser moves the minimum by less than the tolerance
    // measures (the previous f starts below it), so a round must cut its own
    // starting residual instead; with the tolerance alone every round but the
    // last took no iteration and the result was hardly reweighted. Rounds
    // stop once the new weights move f by a fraction of the tolerance.
    const double start = relative_residual(op, rhs, f.values);
    if (start < kTotalVariationRoundReduction * solver.tolerance) break;
    SolverOptions so = solver;
    so.tolerance = std::min(solver.tolerance, kTotalVariationRoundReduction * start);
    solve_and_report(op, rhs, f.values, so, stats, reporter);
  }
}

// Adds the screening term to op and its target to rhs. The target of the
// pinning is the isovalue (eq. 12) of the unscreened solution, estimated on a
// grid coarsened up to x_level times, whose prolongation (in x) also starts
// the solve.
void add_screening(EnergyOperator& op,
                   StoredField& rhs,
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
  op.screening().add_target(target, *rhs.nodes, rhs.values.data());
  reporter.debug(format_message("recon: screening term ", seconds_since(t_screening), " s"));
}

// Energies (1), (3), (4): one solve (screened when options.screening > 0),
// restricted to a band around the samples where that pays. Returns f on every
// node, or with band_only on the fine band's stored nodes.
StoredField solve_quadratic(const GridGeometry& grid,
                            StoredField rhs,
                            const std::vector<Eigen::Vector3f>& points,
                            const ReconOptions& options,
                            bool band_only,
                            ReconStats& stats,
                            Reporter& reporter) {
  const SolverOptions& solver = options.solver;
  const double ell = reference_length(grid);
  const double weight = options.energy == SmoothnessEnergy::kMembrane ? options.lambda : options.lambda * ell * ell;
  EnergyOperator op(grid, options.energy, weight);
  // The solve starts on a coarsened grid (see solve_with_bands).
  int x_level = start_level(grid, options, band_only);
  std::vector<double> x;
  if (options.screening > 0.0) {
    add_screening(op, rhs, points, options, x_level, x, reporter);
  } else {
    // From zero, on the coarsest grid the solve may start on.
    GridGeometry start = grid;
    int levels = 0;
    for (; levels < x_level && start.can_coarsen(3); ++levels) start = start.coarsened();
    x_level = levels;
    x.assign(start.num_nodes(), 0.0);
  }
  LevelSolution f = solve_with_bands(
      op, std::move(rhs), points, band_only ? solver.band_only_voxels : solver.band_voxels, band_only, x_level,
      std::move(x), reporter, [&](const EnergyOperator& o, std::vector<double>&& b, std::vector<double>& xs) {
        // Keeping only the band, the CG vectors are the peak: single
        // precision halves them (see docs/recon.md, "Memory").
        solve_and_report(o, std::move(b), xs, solver, stats, reporter,
                         band_only ? VectorPrecision::kSingle : VectorPrecision::kDouble);
      });
  stats.band_nodes = f.band_nodes;
  return std::move(f.x);
}

// Eq. 12 on a function on every node or on a band (the samples' cells are active).
double mean_at_samples(const GridGeometry& g, const StoredField& f, const std::vector<Eigen::Vector3f>& points) {
  double sum = 0.0;
  for (const auto& p : points) sum += sample_trilinear(g, f, p.cast<double>());
  return sum / static_cast<double>(points.size());
}

// The isosurface (sec. 4.4) at f's isovalue, trimmed away from the samples.
void extract_surface(const GridGeometry& grid,
                     const ImplicitFunction& fn,
                     const std::vector<Eigen::Vector3f>& points,
                     const ReconOptions& options,
                     ReconResult& result) {
  ReconStats& stats = result.stats;
  result.mesh = extract_isosurface(grid, fn.f, fn.isovalue);
  stats.faces_before_trim = result.mesh.faces.size();
  if (options.trim.enabled) {
    stats.faces_trimmed = trim_far_from_samples(result.mesh, points, options.trim.distance_voxels * grid.spacing,
                                                options.trim.sparse_reach);
  }
}

// recon.resolution 0: the grid the samples' density supports
// (sample_density.h), refined by recon.density_refinement, no finer than the
// memory budget allows. The trim distance keeps its length: it is in voxels
// of the density's grid, the gaps between samples it must bridge being a
// matter of their spacing.
void choose_resolution_from_density(const BoundingBox& box,
                                    const std::vector<Eigen::Vector3f>& points,
                                    bool clamp_to_budget,
                                    ReconOptions& options,
                                    ReconStats& stats,
                                    Reporter& reporter) {
  const int density_grid = resolution_from_density(box, points, options);
  const int refined = std::clamp(static_cast<int>(std::lround(options.density_refinement * density_grid / 8.0)) * 8,
                                 kMinDensityResolution, kMaxDensityResolution);
  const double trim_voxels = options.trim.distance_voxels;
  const auto scale_trim = [&](int resolution) {
    options.trim.distance_voxels = trim_voxels * resolution / density_grid;
    options.solver.band_only_voxels =
        std::max(options.solver.band_only_voxels, static_cast<int>(std::ceil(options.trim.distance_voxels + 2.0)));
  };
  options.resolution = refined;
  scale_trim(refined);
  const std::size_t budget = memory_budget_bytes(options);
  if (clamp_to_budget && estimate_peak_bytes(make_domain(box, options), points, options) > budget) {
    // The largest grid within the budget; when none fits, check_memory_budget refuses the run.
    const int fitting = largest_resolution_within(box, points, options, budget);
    if (fitting > 0) {
      options.resolution = std::min(refined, fitting);
      scale_trim(options.resolution);
    }
  }
  stats.samples_per_occupied_cell = mean_samples_per_occupied_cell(box, points, options, options.resolution);
  reporter.info(format_message("recon: resolution ", options.resolution, " (", stats.samples_per_occupied_cell,
                               " samples per occupied cell; ", density_grid, " from the samples' density",
                               options.resolution < refined ? ", the memory budget allows no finer" : "",
                               "), trim distance ", options.trim.distance_voxels, " voxels"));
}

}  // namespace

void begin_run(const PointCloud& input, const ReconOptions& options) {
  options.validate();
  check_reconstructable(input, "input points");
#ifdef _OPENMP
  if (options.threads > 0) omp_set_num_threads(options.threads);
#endif
}

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

RunGrid choose_run_grid(const OrientedSamples& samples,
                        const ReconOptions& options,
                        bool clamp_to_budget,
                        ReconStats& stats,
                        Reporter& reporter) {
  RunGrid run{GridGeometry{}, options};
  ReconOptions& unit_options = run.options;
  unit_options.voxel_size = options.voxel_size / samples.frame.scale;
  const BoundingBox box = bounding_box(samples.points);
  if (unit_options.voxel_size <= 0.0 && unit_options.resolution == 0) {
    choose_resolution_from_density(box, samples.points, clamp_to_budget, unit_options, stats, reporter);
  }
  run.grid = make_domain(box, unit_options);
  stats.grid_dims = run.grid.dims;
  stats.resolution = unit_options.voxel_size > 0.0 ? 0 : unit_options.resolution;
  stats.voxel_size = run.grid.spacing * samples.frame.scale;
  return run;
}

ImplicitFunction solve_implicit_function(const OrientedSamples& samples,
                                         const GridGeometry& grid,
                                         const ReconOptions& unit_options,
                                         ReconStats& stats,
                                         Reporter& reporter) {
  const std::vector<Eigen::Vector3f>& points = samples.points;
  const auto t_field = Clock::now();
  reporter.begin("orientation field", 0);
  reporter.info(format_message("recon: grid ", grid.dims.x(), "x", grid.dims.y(), "x", grid.dims.z(), ", voxel ",
                               grid.spacing, ", ", points.size(), " samples"));
  const bool band_only = keeps_only_band(grid, unit_options);
  StoredField rhs = orientation_rhs(grid, samples, unit_options, band_only);
  reporter.end();
  stats.seconds_field = seconds_since(t_field);

  // Energy minimisation (sec. 3.4, 4.2, 4.3).
  const auto t_solve = Clock::now();
  reporter.begin("solve", 0);
  ImplicitFunction fn;
  if (unit_options.energy == SmoothnessEnergy::kTotalVariation) {
    ScalarGrid f(grid);
    solve_total_variation(grid, rhs.values, unit_options, f, stats, reporter);
    fn.f = StoredField{std::make_shared<const ActiveNodes>(ActiveNodes::all(grid)), std::move(f.values)};
  } else {
    fn.f = solve_quadratic(grid, std::move(rhs), points, unit_options, band_only, stats, reporter);
  }
  for (double v : fn.f.values) {
    if (!std::isfinite(v)) throw NumericalError("recon", "the implicit function is not finite");
  }
  reporter.end();
  stats.seconds_solve = seconds_since(t_solve);
  fn.isovalue = mean_at_samples(grid, fn.f, points);
  stats.isovalue = fn.isovalue;
  return fn;
}

void remove_debris_and_report(const DebrisOptions& options,
                              ReconResult& result,
                              Reporter& reporter,
                              const DebrisSupport& support) {
  const DebrisReport& debris = result.stats.debris = remove_debris(result.mesh, options, support);
  if (debris.components_removed > 0) {
    reporter.info(format_message("recon: removed ", debris.components_removed, " of ", debris.components,
                                 " pieces as debris: ", debris.faces_removed, " faces, area ", debris.area_removed,
                                 " (", 100.0 * debris.area_removed / (debris.area_removed + debris.area_kept),
                                 "% of the surface)"));
  }
}

ReconResult reconstruct_surface(const PointCloud& input, const ReconOptions& options, Reporter& reporter) {
  begin_run(input, options);
  ReconResult result;
  ReconStats& stats = result.stats;
  const OrientedSamples samples = usable_samples(input, options, stats, reporter);
  const RunGrid run = choose_run_grid(samples, options, /*clamp_to_budget=*/true, stats, reporter);
  check_memory_budget(bounding_box(samples.points), samples.points, run.options);  // before anything grid-sized
  const GridGeometry& grid = run.grid;
  const bool band_only = keeps_only_band(grid, run.options);
  ImplicitFunction fn = solve_implicit_function(samples, grid, run.options, stats, reporter);

  if (band_only) release_freed_memory();
  const auto t_mesh = Clock::now();
  reporter.begin("isosurface", 0);
  extract_surface(grid, fn, samples.points, run.options, result);
  reporter.end();
  stats.seconds_mesh = seconds_since(t_mesh);
  if (result.mesh.faces.empty()) {
    throw NumericalError("recon", "the isosurface is empty (the orientations may be inconsistent)");
  }
  to_world(samples.frame, result.mesh);
  remove_debris_and_report(options.debris, result, reporter,
                           {&input.positions, &input.confidence, options.trim.distance_voxels * stats.voxel_size});
  ScalarGrid& f = result.function;
  f.geometry = grid;
  f.geometry.origin = samples.frame.to_world(f.geometry.origin);
  f.geometry.spacing *= samples.frame.scale;
  if (fn.f.nodes->is_all()) f.values = std::move(fn.f.values);
  reporter.info(format_message("recon: isovalue ", stats.isovalue, ", ", result.mesh.num_vertices(), " vertices, ",
                               result.mesh.num_faces(), " faces (", stats.faces_trimmed, " trimmed)"));
  return result;
}

}  // namespace hos::recon
