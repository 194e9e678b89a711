#include "tests/refine/rock_fixture.h"

#include "refine/mesh_geometry.h"
#include "synth/dataset.h"
#include "synth/scene.h"

namespace hos::refine::testing {

namespace {

synth::Scene object_scene(const std::string& name) {
  synth::SceneOptions options;
  options.name = name;
  return synth::make_scene(options);
}

}  // namespace

TriangleMesh rock_truth() { return synth::merged_mesh(object_scene("rock"), false); }

RockScene make_object_scene(const std::string& name, int num_views, int levels) {
  const synth::Scene scene = object_scene(name);
  synth::DatasetOptions options;
  options.num_views = num_views;
  options.width = 400;
  options.height = 300;
  options.num_points = 100;
  const synth::RenderedDataset data = synth::render_dataset(scene, options);
  RockScene rock;
  rock.truth = synth::merged_mesh(scene, false);
  std::size_t k = 0;
  for (const auto& [id, image] : data.model.images) {
    rock.views.push_back(make_view(data.model.camera_of(image), image, data.views[k++].color, levels, image.name));
  }
  return rock;
}

RockScene make_rock_scene(int num_views, int levels) { return make_object_scene("rock", num_views, levels); }

TriangleMesh smoothed(const TriangleMesh& mesh, int rounds) {
  TriangleMesh out = mesh;
  const VertexRings rings = vertex_rings(mesh);
  for (int r = 0; r < rounds; ++r) {
    std::vector<Eigen::Vector3f> next = out.vertices;
    for (std::size_t v = 0; v < next.size(); ++v) {
      Eigen::Vector3f mean = Eigen::Vector3f::Zero();
      for (int k = rings.offsets[v]; k < rings.offsets[v + 1]; ++k) mean += out.vertices[rings.neighbors[k]];
      next[v] = 0.5f * (out.vertices[v] + mean / static_cast<float>(rings.degree(static_cast<int>(v))));
    }
    out.vertices = std::move(next);
  }
  return out;
}

double enclosed_volume(const TriangleMesh& mesh) {
  double six_v = 0.0;
  for (const Eigen::Vector3i& f : mesh.faces) {
    const Eigen::Vector3d a = mesh.vertices[f[0]].cast<double>(), b = mesh.vertices[f[1]].cast<double>(),
                          c = mesh.vertices[f[2]].cast<double>();
    six_v += a.dot(b.cross(c));
  }
  return six_v / 6.0;
}

}  // namespace hos::refine::testing
