#include "tests/mvs/synthetic_workspace.h"

#include "core/ply_io.h"

namespace hos::mvs_testing {

const SyntheticWorkspace& synthetic_workspace() {
  static const SyntheticWorkspace instance = [] {
    SyntheticWorkspace s;
    s.dir = std::make_unique<hos::testing::TempDir>("hos-mvs-test");
    synth::SceneOptions scene_options;
    synth::DatasetOptions options;
    options.num_views = 12;
    options.width = 320;
    options.height = 240;
    const synth::Scene scene = synth::make_scene(scene_options);
    synth::write_dataset(s.dir->path() / "scene", scene, scene_options, options);
    s.truth = synth::render_dataset(scene, options);
    s.workspace = load_undistorted_workspace(s.dir->path() / "scene");
    s.diagonal = bounding_box(read_mesh_ply(s.dir->path() / "scene" / "gt_objects.ply").vertices).diagonal();
    return s;
  }();
  return instance;
}

}  // namespace hos::mvs_testing
