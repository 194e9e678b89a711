// hos-synth's option tables (section "synth"): ranges and documentation of
// the scene, dataset and video options in one place; hos-synth's flags go
// through them, and each options struct's validate() checks its table and
// adds only the rules that involve two options.
#pragma once

#include "core/option_set.h"
#include "synth/dataset.h"
#include "synth/scene.h"
#include "synth/video.h"

namespace hos::synth {

void register_options(OptionSet& set, SceneOptions& o);
void register_options(OptionSet& set, DatasetOptions& o);
// Keys under "video." (the clip: video.name).
void register_options(OptionSet& set, VideoOptions& o);

}  // namespace hos::synth
