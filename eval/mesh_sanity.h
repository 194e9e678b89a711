// Topological sanity of a triangle mesh: watertightness, manifoldness,
// orientation, components, Euler characteristic, degenerate faces.
#pragma once

#include <cstddef>
#include <optional>

#include "core/types.h"

namespace hos::eval {

struct MeshSanity {
  std::size_t vertices = 0;  // referenced by at least one face
  std::size_t unreferenced_vertices = 0;
  std::size_t faces = 0;
  std::size_t edges = 0;                  // undirected
  std::size_t boundary_edges = 0;         // with one face
  std::size_t non_manifold_edges = 0;     // with three or more faces
  std::size_t non_manifold_vertices = 0;  // whose faces form more than one fan
  std::size_t inconsistent_edges = 0;     // two faces traverse the edge in the same direction
  std::size_t degenerate_faces = 0;       // repeated vertex index or zero area
  std::size_t components = 0;             // connected through shared vertices
  long long euler_characteristic = 0;     // V - E + F over referenced vertices
  bool edge_manifold = false;             // no edge with more than two faces
  bool vertex_manifold = false;
  bool watertight = false;  // closed and edge-manifold: every edge has two faces
  bool consistently_oriented = false;
  // Sum of the genera of the components, when the mesh is closed, manifold
  // and oriented: (2 * components - euler_characteristic) / 2.
  std::optional<long long> genus;
};

// Degenerate faces have a repeated index or an area below
// relative_area_epsilon * (bounding-box diagonal)^2.
MeshSanity check_mesh_sanity(const TriangleMesh& mesh, double relative_area_epsilon = 1e-14);

}  // namespace hos::eval
