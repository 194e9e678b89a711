// Options of the photometric mesh refinement, mapped 1:1 onto the "refine:"
// section of the YAML config by register_options.
#pragma once

namespace hos {
class OptionSet;
}

namespace hos::refine {

// The regulariser of the refinement (Pan & Skala sec. 3.2 carried from the
// implicit function over to the surface's positions).
enum class Regularizer {
  kMembrane = 1,   // x^T L x (eq. (1)'s analogue, the usual area term): shrinks curved parts
  kThinPlate = 2,  // |L x|^2 (eq. (3)'s analogue, a discrete bi-Laplacian): planes cost nothing
};

struct RefineOptions {
  // false: the stage passes the recon mesh through unchanged. The defaults
  // below were chosen on the real leave-one-out benchmark (docs/refine.md).
  bool enabled = true;
  Regularizer regularizer = Regularizer::kThinPlate;
  // Weight of the regulariser against the photometric targets (each vertex's
  // target weight is its ZNCC confidence in [0, 1]).
  double lambda = 1.0;
  // Image scales, coarse to fine: level l matches at 1/2^l of the photos'
  // resolution; the finest used is 0.
  int levels = 3;
  // Levels whose photos are smaller than this on the longest side are not used.
  int min_level_size = 600;
  // Refinement rounds (each: visibility, search, solve) per level, and at
  // least min_rounds in all: a round moves a vertex about half way to the
  // surface its patch sees, and coarse levels supply the first rounds, so
  // the finest level adds rounds only when fewer levels are usable (small
  // photos).
  int iterations = 1;
  int min_rounds = 2;
  // Before each level, edges longer than this many pixels of the level (in
  // the view that resolves them finest) are split, so the mesh can take the
  // detail the photos show; 0 keeps the input's faces.
  double edge_pixels = 8.0;
  int max_faces = 300000;  // the subdivision stops here (time and texture's budget)
  // Normal offsets tried per side of a vertex, and their spacing in pixels of
  // the reference view at the level's scale.
  int search_steps = 4;
  double step_pixels = 0.75;
  // Patch of patch_size x patch_size samples in the tangent plane, spaced
  // sample_pixels apart in the reference view.
  int patch_size = 9;
  double sample_pixels = 1.5;
  // Samples off the surface the reference sees (past a silhouette, across a
  // depth edge) are left out of the patch; with fewer than this fraction left
  // the vertex gets no target. Below 1, vertices near silhouettes and on thin
  // parts (narrower than the patch) are refined too, where the recon mesh is
  // least accurate (docs/refine.md).
  double min_patch_coverage = 0.6;
  // Vertices about this many pixels of the finest level apart are searched,
  // the others take the nearest searched ones' targets (a patch is
  // patch_size * sample_pixels wide, so its neighbours' searches largely
  // repeat it); 0 searches every vertex. Off by default: the finest level
  // is where the held-out PSNR is won (spacing every level at 4 or 8 cost
  // fountain-P11 0.12-0.18 dB, docs/refine.md).
  double search_spacing = 0.0;
  // The same at the coarser levels (level > 0), whose rounds only bring the
  // surface near enough for the finest level's search, which sees every
  // vertex: at 4, refine's CPU on the Strecha sets falls to 0.6-0.7x at the
  // same held-out PSNR (docs/refine.md).
  double coarse_search_spacing = 4.0;
  int max_views = 4;           // views compared with the reference per vertex
  double min_angle_deg = 4.0;  // baseline between reference and compared view at the vertex
  double max_angle_deg = 60.0;
  double max_incidence_deg = 75.0;  // views seeing the surface more grazing than this are not used
  double min_zncc = 0.5;            // a best score below this gives the vertex no target
  // Each vertex is also held at its position with this weight, so the linear
  // system is well posed where the photos say nothing.
  double anchor_weight = 0.05;
  // Rounds stop when the mean photometric score improves by less than this.
  double min_improvement = 1e-3;
  // Time budget (wall seconds); the mesh after the last finished round is
  // kept. Refine takes 36-60 s on the Strecha sets; 120 s cut a fountain run
  // on a machine loaded 5-fold after 3 of its 6 rounds (docs/refine.md).
  double max_seconds = 600.0;
  int threads = 0;  // OpenMP threads; 0 = all cores

  // Throws ConfigError naming the offending option.
  void validate() const;
};

// Registers every option under the section "refine".
void register_options(OptionSet& set, RefineOptions& options);

}  // namespace hos::refine
