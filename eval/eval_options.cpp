#include "eval/eval_options.h"

#include <limits>
#include <sstream>

#include "core/error.h"

namespace hos::eval {

void register_options(OptionSet& set, MeshEvalOptions& o) {
  set.add("thresholds", o.thresholds, "F-score thresholds as fractions of the truth's bbox diagonal, comma-separated");
  set.add("samples", o.distance.num_samples, "surface samples per mesh", std::size_t{1000}, std::size_t{1000000000});
  set.add("seed", o.distance.seed, "sampling seed", std::uint64_t{0}, std::numeric_limits<std::uint64_t>::max());
  set.add("min_views", o.visible_min_views, "views that must see a true face (with --visible-in)", 1, 100000);
  set.add_flag("--thresholds", "thresholds");
  set.add_flag("--samples", "samples");
  set.add_flag("--seed", "seed");
  set.add_flag("--min-views", "min_views");
}

void resolve_thresholds(MeshEvalOptions& o) {
  o.distance.thresholds.clear();
  std::stringstream ss(o.thresholds);
  std::string item;
  while (std::getline(ss, item, ',')) {
    // "0.01, 0.02" as well as "0.01,0.02"
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    const std::optional<double> value = parse_number<double>(item);
    if (!value) throw ConfigError("eval.thresholds", "'" + item + "' " + number_problem<double>(item));
    o.distance.thresholds.push_back(*value);
  }
  o.distance.validate();
}

#ifdef HOS_EVAL_HAS_RENDER
void register_options(OptionSet& set, CommonOptions& o) {
  set.add("worst_tiles", o.worst_tiles,
          "list this many tiles of the photo, those carrying most of the first run's squared error first",
          std::size_t{0}, std::size_t{1000000});
  set.add("tile_size", o.tile_size, "tile side (pixels)", 1, 1 << 16);
  set.add_flag("--worst-tiles", "worst_tiles");
  set.add_flag("--tile-size", "tile_size");
}
#endif

}  // namespace hos::eval
