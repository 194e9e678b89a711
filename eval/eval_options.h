// hos-eval's option tables (section "eval"): ranges and documentation of the
// measurements' numeric options in one place, applied from the command line
// through OptionSet like a stage's.
#pragma once

#include <string>

#include "core/option_set.h"
#include "eval/surface_distance.h"
#ifdef HOS_EVAL_HAS_RENDER
#include "eval/render_compare.h"
#endif

namespace hos::eval {

// mesh: the surface comparison and the visible part of the truth.
struct MeshEvalOptions {
  SurfaceDistanceOptions distance;
  // Comma-separated; resolve_thresholds fills distance.thresholds from it.
  std::string thresholds = "0.005,0.01,0.02";
  int visible_min_views = 2;  // views that must see a true face (--visible-in)
};
void register_options(OptionSet& set, MeshEvalOptions& o);

// Parses o.thresholds into o.distance.thresholds; ConfigError naming
// eval.thresholds and the item that is not a number.
void resolve_thresholds(MeshEvalOptions& o);

#ifdef HOS_EVAL_HAS_RENDER
// common: the tiles listed (regions and crops are given apart).
void register_options(OptionSet& set, CommonOptions& o);
#endif

}  // namespace hos::eval
