// The refinement tests' scene: hos-synth's rock photographed from a ring of
// views, its true mesh, and meshes of it degraded in known ways.
#pragma once

#include <string>
#include <vector>

#include "core/types.h"
#include "refine/views.h"

namespace hos::refine::testing {

struct RockScene {
  TriangleMesh truth;
  std::vector<RefineView> views;  // with `levels` pyramid levels
};

// hos-synth's rock (seed 1), the true surface.
TriangleMesh rock_truth();

// One object of hos-synth's scenes ("rock", "box", ...) in `num_views`
// photos of 400x300 pixels.
RockScene make_object_scene(const std::string& name, int num_views, int levels);
RockScene make_rock_scene(int num_views, int levels);

// Umbrella-operator smoothing (x <- x + 0.5 L x, `rounds` times): the rock
// loses its bumps and shrinks, as a too-smooth reconstruction does.
TriangleMesh smoothed(const TriangleMesh& mesh, int rounds);

// Enclosed volume of a closed, outward-oriented mesh (divergence theorem).
double enclosed_volume(const TriangleMesh& mesh);

}  // namespace hos::refine::testing
