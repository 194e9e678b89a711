#include "synth/scene.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <tuple>

#include "core/error.h"
#include "synth/shapes.h"
#include "synth/synth_options.h"

namespace hos::synth {
namespace {

std::uint32_t hash3(int x, int y, int z, std::uint32_t seed) {
  std::uint32_t h = seed * 0x9E3779B9u;
  h ^= static_cast<std::uint32_t>(x) * 0x85EBCA6Bu;
  h = (h << 13) | (h >> 19);
  h ^= static_cast<std::uint32_t>(y) * 0xC2B2AE35u;
  h = (h << 17) | (h >> 15);
  h ^= static_cast<std::uint32_t>(z) * 0x27D4EB2Fu;
  h ^= h >> 16;
  h *= 0x7FEB352Du;
  h ^= h >> 15;
  h *= 0x846CA68Bu;
  h ^= h >> 16;
  return h;
}

float hash_unit(int x, int y, int z, std::uint32_t seed) {
  return static_cast<float>(hash3(x, y, z, seed) >> 8) / static_cast<float>(1u << 24);
}

// Trilinear value noise in [0, 1] with a smooth fade.
float value_noise(const Eigen::Vector3f& p, std::uint32_t seed) {
  const int x0 = static_cast<int>(std::floor(p.x()));
  const int y0 = static_cast<int>(std::floor(p.y()));
  const int z0 = static_cast<int>(std::floor(p.z()));
  auto fade = [](float t) { return t * t * (3 - 2 * t); };
  const float fx = fade(p.x() - x0), fy = fade(p.y() - y0), fz = fade(p.z() - z0);
  float v[2][2][2];
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int k = 0; k < 2; ++k) v[i][j][k] = hash_unit(x0 + i, y0 + j, z0 + k, seed);
  auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
  const float x00 = lerp(v[0][0][0], v[1][0][0], fx), x10 = lerp(v[0][1][0], v[1][1][0], fx);
  const float x01 = lerp(v[0][0][1], v[1][0][1], fx), x11 = lerp(v[0][1][1], v[1][1][1], fx);
  return lerp(lerp(x00, x10, fy), lerp(x01, x11, fy), fz);
}

// Sum of octaves, normalised to about [0, 1].
float fbm(const Eigen::Vector3f& p, int octaves, std::uint32_t seed) {
  float sum = 0, amp = 1, norm = 0;
  Eigen::Vector3f q = p;
  for (int o = 0; o < octaves; ++o) {
    sum += amp * value_noise(q, seed + 101u * o);
    norm += amp;
    amp *= 0.5f;
    q = 2.03f * q + Eigen::Vector3f(17.1f, 3.7f, 9.2f);
  }
  return sum / norm;
}

// Distance to the nearest random feature point of a cell grid (Worley noise),
// in cell units.
float cell_distance(const Eigen::Vector3f& p, std::uint32_t seed) {
  const int x0 = static_cast<int>(std::floor(p.x()));
  const int y0 = static_cast<int>(std::floor(p.y()));
  const int z0 = static_cast<int>(std::floor(p.z()));
  float best = 10.0f;
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k) {
        const int cx = x0 + i, cy = y0 + j, cz = z0 + k;
        const Eigen::Vector3f f(cx + hash_unit(cx, cy, cz, seed), cy + hash_unit(cx, cy, cz, seed + 1),
                                cz + hash_unit(cx, cy, cz, seed + 2));
        best = std::min(best, (p - f).norm());
      }
  return best;
}

Eigen::Vector3f random_colour(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.05f, 0.85f);
  return Eigen::Vector3f(u(rng), u(rng), u(rng));
}

// An albedo function: a blend of palette colours by multi-scale noise, spots
// of a contrasting colour and warped stripes. scale is the feature size of the
// coarsest pattern in world units.
render::ProceduralAlbedo make_albedo(std::uint32_t seed, float scale) {
  std::mt19937 rng(seed);
  const Eigen::Vector3f a = random_colour(rng), b = random_colour(rng), c = random_colour(rng);
  const Eigen::Vector3f spot = random_colour(rng), stripe = random_colour(rng);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  const Eigen::Vector3f stripe_dir = Eigen::Vector3f(u(rng), u(rng), u(rng)).normalized();
  const float inv = 1.0f / scale;
  return [=](const Eigen::Vector3f& x) -> Eigen::Vector3f {
    const Eigen::Vector3f p = x * inv;
    const float n1 = fbm(2.0f * p, 5, seed + 11);
    const float n2 = fbm(7.0f * p, 3, seed + 23);
    Eigen::Vector3f col = a + (b - a) * std::clamp(1.8f * (n1 - 0.5f) + 0.5f, 0.0f, 1.0f);
    col = col + (c - col) * std::clamp(2.0f * (n2 - 0.5f) + 0.3f, 0.0f, 1.0f) * 0.6f;
    const float warp = fbm(3.0f * p, 2, seed + 37);
    const float s = std::sin(2 * std::numbers::pi_v<float> * (5.0f * p.dot(stripe_dir) + 2.0f * warp));
    if (s > 0.6f) col = 0.4f * col + 0.6f * stripe;
    const float d = cell_distance(9.0f * p, seed + 53);
    if (d < 0.28f)
      col = spot;
    else if (d < 0.34f)
      col *= 0.3f;  // dark rim: a corner-rich edge
    const float fine = fbm(25.0f * p, 2, seed + 71);
    col *= 0.7f + 0.6f * fine;
    return col.cwiseMax(Eigen::Vector3f::Constant(0.02f)).cwiseMin(Eigen::Vector3f::Constant(0.95f));
  };
}

// Vertex normals as area-weighted face normals.
void compute_normals(TriangleMesh& mesh) {
  mesh.normals.assign(mesh.vertices.size(), Eigen::Vector3f::Zero());
  for (const Eigen::Vector3i& f : mesh.faces) {
    const Eigen::Vector3f n =
        (mesh.vertices[f[1]] - mesh.vertices[f[0]]).cross(mesh.vertices[f[2]] - mesh.vertices[f[0]]);
    for (int k = 0; k < 3; ++k) mesh.normals[f[k]] += n;
  }
  for (Eigen::Vector3f& n : mesh.normals) n = n.squaredNorm() > 0 ? n.normalized() : Eigen::Vector3f::UnitY();
}

TriangleMesh make_rock(std::uint32_t seed, float radius) {
  TriangleMesh m = icosphere(5);
  const Eigen::Vector3f stretch(1.15f, 0.85f, 1.0f);
  for (Eigen::Vector3f& v : m.vertices) {
    const float d = fbm(1.6f * v + Eigen::Vector3f::Constant(3.0f), 5, seed + 401);
    v = (radius * (0.8f + 0.45f * d) * v).cwiseProduct(stretch);
  }
  return m;
}

TriangleMesh make_torus(float major, float minor, int nu, int nv) {
  TriangleMesh m;
  for (int i = 0; i < nu; ++i) {
    const float u = 2 * std::numbers::pi_v<float> * i / nu;
    for (int j = 0; j < nv; ++j) {
      const float v = 2 * std::numbers::pi_v<float> * j / nv;
      m.vertices.emplace_back((major + minor * std::cos(v)) * std::cos(u), minor * std::sin(v),
                              (major + minor * std::cos(v)) * std::sin(u));
    }
  }
  auto id = [&](int i, int j) { return ((i + nu) % nu) * nv + (j + nv) % nv; };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      // Counter-clockwise seen from outside (checked by the outward normal test).
      m.faces.emplace_back(id(i, j), id(i, j + 1), id(i + 1, j + 1));
      m.faces.emplace_back(id(i, j), id(i + 1, j + 1), id(i + 1, j));
    }
  return m;
}

// A box with rounded edges: a subdivided cube whose points are pushed onto
// the rounded surface (inner box plus a sphere of radius r).
TriangleMesh make_rounded_box(const Eigen::Vector3f& half, float r, int n) {
  TriangleMesh m;
  std::map<std::tuple<int, int, int>, int> index;
  auto vertex = [&](int i, int j, int k) {
    const auto key = std::make_tuple(i, j, k);
    const auto it = index.find(key);
    if (it != index.end()) return it->second;
    const Eigen::Vector3f p = Eigen::Vector3f(2.0f * i / n - 1, 2.0f * j / n - 1, 2.0f * k / n - 1).cwiseProduct(half);
    const Eigen::Vector3f inner = half - Eigen::Vector3f::Constant(r);
    const Eigen::Vector3f q = p.cwiseMax(-inner).cwiseMin(inner);
    const Eigen::Vector3f d = p - q;
    m.vertices.push_back(d.squaredNorm() > 0 ? Eigen::Vector3f(q + r * d.normalized()) : p);
    const int id = static_cast<int>(m.vertices.size()) - 1;
    index.emplace(key, id);
    return id;
  };
  // For each axis and side, a grid on the face; the winding follows the
  // outward normal.
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
      for (int s = 0; s < n; ++s)
        for (int t = 0; t < n; ++t) {
          auto v = [&](int ds, int dt) {
            int c[3];
            c[axis] = side * n;
            c[a1] = s + ds;
            c[a2] = t + dt;
            return vertex(c[0], c[1], c[2]);
          };
          const int v00 = v(0, 0), v10 = v(1, 0), v11 = v(1, 1), v01 = v(0, 1);
          if (side == 1) {
            m.faces.emplace_back(v00, v10, v11);
            m.faces.emplace_back(v00, v11, v01);
          } else {
            m.faces.emplace_back(v00, v11, v10);
            m.faces.emplace_back(v00, v01, v11);
          }
        }
    }
  }
  return m;
}

TriangleMesh make_ground(float y, float half, int n) {
  TriangleMesh m;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) m.vertices.emplace_back(-half + 2 * half * i / n, y, -half + 2 * half * j / n);
  auto id = [&](int i, int j) { return i * (n + 1) + j; };
  // Normal towards up (-y).
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      m.faces.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      m.faces.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  return m;
}

void place(TriangleMesh& m, const Eigen::Matrix3f& R, const Eigen::Vector3f& t) {
  for (Eigen::Vector3f& v : m.vertices) v = R * v + t;
}

void append(TriangleMesh& to, const TriangleMesh& m) {
  const int offset = static_cast<int>(to.vertices.size());
  to.vertices.insert(to.vertices.end(), m.vertices.begin(), m.vertices.end());
  for (const Eigen::Vector3i& f : m.faces) to.faces.push_back(f + Eigen::Vector3i::Constant(offset));
}

// A round railing: kRailingBars upright bars of kRailingBarWidth square
// section on a circle, between two rings as thick, centred at the origin, so
// every view of a ring around it sees bars across the photo. All of it is
// thin structure: with the railing filling the photo, a bar is about 3
// pixels wide in a 2048-pixel photo and under one pixel at 640.
constexpr int kRailingBars = 20;
constexpr float kRailingBarWidth = 0.0015f;
TriangleMesh make_railing() {
  const float radius = 0.5f, half_height = 0.4f;
  TriangleMesh m;
  for (int i = 0; i < kRailingBars; ++i) {
    TriangleMesh bar = make_rounded_box(Eigen::Vector3f(kRailingBarWidth / 2, half_height, kRailingBarWidth / 2),
                                        kRailingBarWidth / 8, 4);
    const float a = 2 * std::numbers::pi_v<float> * i / kRailingBars;
    place(bar, Eigen::AngleAxisf(-a, Eigen::Vector3f::UnitY()).toRotationMatrix(),
          Eigen::Vector3f(radius * std::cos(a), 0.0f, radius * std::sin(a)));
    append(m, bar);
  }
  for (const float y : {-half_height - kRailingBarWidth / 2, half_height + kRailingBarWidth / 2}) {
    TriangleMesh ring = make_torus(radius, kRailingBarWidth / 2, 256, 6);
    place(ring, Eigen::Matrix3f::Identity(), Eigen::Vector3f(0.0f, y, 0.0f));
    append(m, ring);
  }
  return m;
}

// A lantern (a rounded box) hanging on a thin wire from the arm of a thin
// upright pole that stands at the level of the lowest point of `around`
// (the other objects), in front of their +z side, sized by their height h:
// pole 0.015 h wide and 1.1 h tall, wire 0.004 h, lantern 0.18 h wide, its
// centre at mid height 0.25 h beyond the objects. Seen from +z the objects
// are the background behind it; pole and wire are a few pixels and about one
// pixel wide in a 640-pixel view of the default scene.
TriangleMesh make_hanging_lantern(const BoundingBox& around) {
  const float h = around.max.y() - around.min.y();
  const float foot_y = around.max.y(), top_y = foot_y - 1.1f * h;  // up is -y
  const float x = 0.5f * (around.min.x() + around.max.x());
  const float pole_z = around.max.z() + 0.05f * h, lantern_z = pole_z + 0.2f * h;
  const float pole = 0.015f * h, wire = 0.004f * h, lantern = 0.09f * h;
  const float lantern_y = 0.5f * (around.min.y() + around.max.y());
  // An axis-aligned rounded box between two corners.
  auto bar = [](const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, int n) {
    const Eigen::Vector3f half = 0.5f * (hi - lo);
    TriangleMesh m = make_rounded_box(half, 0.25f * half.minCoeff(), n);
    place(m, Eigen::Matrix3f::Identity(), 0.5f * (lo + hi));
    return m;
  };
  TriangleMesh m = bar({x - pole / 2, top_y, pole_z - pole / 2}, {x + pole / 2, foot_y, pole_z + pole / 2}, 8);
  append(m, bar({x - pole / 2, top_y, pole_z + pole / 2}, {x + pole / 2, top_y + pole, lantern_z + pole}, 6));
  append(m, bar({x - wire / 2, top_y + pole, lantern_z - wire / 2},
                {x + wire / 2, lantern_y - lantern, lantern_z + wire / 2}, 6));
  append(m, bar({x - lantern, lantern_y - lantern, lantern_z - lantern},
                {x + lantern, lantern_y + lantern, lantern_z + lantern}, 12));
  return m;
}

Rgb8 to_srgb8(const Eigen::Vector3f& linear) {
  Rgb8 c;
  for (int k = 0; k < 3; ++k) {
    const float x = std::clamp(linear[k], 0.0f, 1.0f);
    const float s = x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
    c[k] = static_cast<std::uint8_t>(std::lround(255.0f * s));
  }
  return c;
}

}  // namespace

void SceneOptions::validate() const { check_option_table("synth", *this); }

std::vector<std::string> scene_names() { return {"default", "rock", "torus", "box", "railing"}; }

Scene make_scene(const SceneOptions& options) {
  options.validate();
  Scene scene;
  std::mt19937 rng(options.seed * 7919u + 13u);
  std::uniform_real_distribution<float> jitter(-0.08f, 0.08f), angle(0.0f, 2 * std::numbers::pi_v<float>);
  const bool all = options.name == "default";
  auto add = [&](TriangleMesh mesh, const std::string& name, std::uint32_t salt, float pattern_scale) {
    compute_normals(mesh);
    render::RenderObject obj;
    obj.material.procedural = make_albedo(options.seed * 1000u + salt, pattern_scale);
    mesh.colors.resize(mesh.vertices.size());
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
      mesh.colors[i] = to_srgb8(obj.material.procedural(mesh.vertices[i]));
    obj.mesh = std::move(mesh);
    scene.objects.push_back(std::move(obj));
    scene.is_ground.push_back(false);
    scene.names.push_back(name);
  };
  if (all || options.name == "rock") {
    TriangleMesh rock = make_rock(options.seed, 0.6f);
    place(rock, Eigen::AngleAxisf(angle(rng), Eigen::Vector3f::UnitY()).toRotationMatrix(),
          Eigen::Vector3f(jitter(rng), 0.0f, jitter(rng)));
    add(std::move(rock), "rock", 1, 1.0f);
  }
  if (all || options.name == "torus") {
    TriangleMesh torus = make_torus(0.38f, 0.14f, 96, 32);
    const Eigen::Matrix3f R =
        (Eigen::AngleAxisf(angle(rng), Eigen::Vector3f::UnitY()) * Eigen::AngleAxisf(0.5f, Eigen::Vector3f::UnitX()))
            .toRotationMatrix();
    place(torus, R, all ? Eigen::Vector3f(1.05f + jitter(rng), 0.25f, 0.45f + jitter(rng)) : Eigen::Vector3f::Zero());
    add(std::move(torus), "torus", 2, 0.6f);
  }
  if (all || options.name == "box") {
    TriangleMesh box = make_rounded_box(Eigen::Vector3f(0.32f, 0.28f, 0.26f), 0.07f, 24);
    place(box, Eigen::AngleAxisf(angle(rng), Eigen::Vector3f::UnitY()).toRotationMatrix(),
          all ? Eigen::Vector3f(-0.95f + jitter(rng), 0.32f, -0.35f + jitter(rng)) : Eigen::Vector3f::Zero());
    add(std::move(box), "box", 3, 0.6f);
  }
  if (options.name == "railing") add(make_railing(), "railing", 5, 0.3f);
  auto objects_box = [&scene] {
    BoundingBox box;
    for (const render::RenderObject& o : scene.objects)
      for (const Eigen::Vector3f& v : o.mesh.vertices) box.extend(v);
    return box;
  };
  if (options.hanging_object) add(make_hanging_lantern(objects_box()), "lantern", 6, 0.15f);
  const BoundingBox box = objects_box();
  scene.centre = box.center();
  scene.radius = 0.0f;
  for (const render::RenderObject& o : scene.objects)
    for (const Eigen::Vector3f& v : o.mesh.vertices) scene.radius = std::max(scene.radius, (v - scene.centre).norm());
  if (options.ground_plane) {
    // Just below the lowest point (largest y, since up is -y).
    TriangleMesh ground = make_ground(box.max.y() + 0.002f, 2.5f * scene.radius, 48);
    for (Eigen::Vector3f& v : ground.vertices) v.x() += scene.centre.x(), v.z() += scene.centre.z();
    add(std::move(ground), "ground", 4, 1.2f);
    scene.is_ground.back() = true;
  }
  return scene;
}

TriangleMesh merged_mesh(const Scene& scene, bool with_ground) {
  TriangleMesh out;
  for (std::size_t o = 0; o < scene.objects.size(); ++o) {
    if (scene.is_ground[o] && !with_ground) continue;
    const TriangleMesh& m = scene.objects[o].mesh;
    const int offset = static_cast<int>(out.vertices.size());
    out.vertices.insert(out.vertices.end(), m.vertices.begin(), m.vertices.end());
    out.normals.insert(out.normals.end(), m.normals.begin(), m.normals.end());
    out.colors.insert(out.colors.end(), m.colors.begin(), m.colors.end());
    for (const Eigen::Vector3i& f : m.faces) out.faces.push_back(f + Eigen::Vector3i::Constant(offset));
  }
  return out;
}

}  // namespace hos::synth
