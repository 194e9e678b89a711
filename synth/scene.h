// Procedural scenes with known truth for hos-synth and the tests: closed
// objects (a noise-displaced "rock", a torus, a rounded box) near the origin
// with a rich, non-repeating albedo (a function of the 3D position: multi-scale
// value noise, spots, stripes) that feature matchers can match, and an
// optional textured ground plane. World "up" is -y (the COLMAP camera's y
// axis points down), so the default light of render/rasterizer.h comes from above.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "render/rasterizer.h"

namespace hos::synth {

struct SceneOptions {
  std::uint32_t seed = 1;
  // "default" (rock, torus, box), "rock", "torus", "box", "railing" (thin bars: synth/scene.cpp).
  // "railing" (thin bars: synth/scene.cpp).
  std::string name = "default";
  bool ground_plane = false;
  // A lantern hanging on a thin wire from the arm of a thin pole, in front of
  // the other objects (make_hanging_lantern in synth/scene.cpp): thin parts
  // with a background behind them.
  bool hanging_object = false;
  void validate() const;  // throws ConfigError
};

struct Scene {
  std::vector<render::RenderObject> objects;         // procedural materials, vertex colours = albedo
  std::vector<bool> is_ground;                       // per object
  std::vector<std::string> names;                    // per object
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();  // of the non-ground objects
  float radius = 1.0f;                               // bounding sphere of the non-ground objects
  Eigen::Vector3f up = Eigen::Vector3f(0, -1, 0);
};

Scene make_scene(const SceneOptions& options);

// The scene's object meshes (positions, normals, colours) in one mesh, the
// ground plane included or not: the ground truth surface.
TriangleMesh merged_mesh(const Scene& scene, bool with_ground);

// Names make_scene accepts.
std::vector<std::string> scene_names();

}  // namespace hos::synth
