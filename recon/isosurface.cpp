#include "recon/isosurface.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <tuple>
#include <utility>
#include <vector>

#include "recon/trim.h"

namespace hos::recon {
namespace {

// ---------------------------------------------------------------------------
// The unit cube. Corners by bit (x = bit 0, y = bit 1, z = bit 2); edge e has
// axis e / 4 and its lower corner's bits along the two other axes in e % 4;
// face 2a + s is the face normal to axis a on side s.

int bit(int c, int axis) { return (c >> axis) & 1; }

std::array<int, 2> other_axes(int a) {
  return a == 0 ? std::array{1, 2} : a == 1 ? std::array{0, 2} : std::array{0, 1};
}

int edge_between(int c0, int c1) {
  const int d = c0 ^ c1;
  const int a = d == 1 ? 0 : d == 2 ? 1 : 2;
  const auto o = other_axes(a);
  return a * 4 + bit(c0, o[0]) + 2 * bit(c0, o[1]);
}

int edge_lower_corner(int e) {
  const auto o = other_axes(e / 4);
  return ((e & 1) << o[0]) | (((e >> 1) & 1) << o[1]);
}

struct Loops {
  std::uint8_t count = 0;
  std::array<std::uint8_t, 4> length{};
  std::array<std::uint8_t, 12> edges{};  // the loops one after the other
};

struct CubeTables {
  // Face corners at local (u, v) = (0,0), (1,0), (0,1), (1,1), u and v the
  // other two axes in increasing order: two cells sharing the face see the
  // same nodes in the same order.
  std::array<std::array<int, 4>, 6> local;
  // The same corners counter-clockwise seen from outside the cube.
  std::array<std::array<int, 4>, 6> ccw;
  std::array<std::uint8_t, 256> ambiguous{};  // faces with four crossings, by bit
  std::array<std::array<bool, 12>, 12> share_face{};
  // Loops for [config * 64 + faces whose inside corners are joined].
  std::vector<Loops> loops;
};

bool inside(int config, int c) { return (config >> c) & 1; }

// The segments on each face run from a crossing where the face's
// counter-clockwise walk enters the inside to one where it leaves, so that
// loops are counter-clockwise seen from outside (the surface lies to the
// left of the walk, seen from f > isovalue). On a face with four crossings
// the exit is the next one forward when the inside corners are separate,
// the next one backward when they are joined.
Loops make_loops(const CubeTables& t, int config, int joined) {
  std::array<int, 12> next;
  next.fill(-1);
  for (int f = 0; f < 6; ++f) {
    const auto& q = t.ccw[f];
    for (int m = 0; m < 4; ++m) {
      if (inside(config, q[m]) || !inside(config, q[(m + 1) % 4])) continue;
      for (int step = 1; step < 4; ++step) {
        const int j = (joined >> f) & 1 ? (m - step + 4) % 4 : (m + step) % 4;
        if (inside(config, q[j]) != inside(config, q[(j + 1) % 4])) {
          next[edge_between(q[m], q[(m + 1) % 4])] = edge_between(q[j], q[(j + 1) % 4]);
          break;
        }
      }
    }
  }
  Loops loops;
  std::array<bool, 12> used{};
  int n = 0;
  for (int e = 0; e < 12; ++e) {
    if (next[e] < 0 || used[e]) continue;
    int len = 0;
    // Each crossing edge is in one loop, each loop has 3+ of the 12 edges.
    for (int x = e; !used[x] && n < 12; x = next[x]) {
      used[x] = true;
      loops.edges[n++] = static_cast<std::uint8_t>(x);
      ++len;
    }
    loops.length[loops.count++] = static_cast<std::uint8_t>(len);
    if (loops.count == loops.length.size()) break;
  }
  return loops;
}

CubeTables make_tables() {
  CubeTables t;
  for (int f = 0; f < 6; ++f) {
    const int a = f / 2, s = f % 2;
    const auto o = other_axes(a);
    for (int l = 0; l < 4; ++l) t.local[f][l] = (s << a) | ((l & 1) << o[0]) | ((l >> 1) << o[1]);
    // (e_u x e_v) . e_a is +1 for a = x, z and -1 for a = y; the outward
    // normal is -e_a on side 0.
    const bool uv_ccw = (a == 1) == (s == 0);
    const auto& c = t.local[f];
    t.ccw[f] = uv_ccw ? std::array{c[0], c[1], c[3], c[2]} : std::array{c[0], c[2], c[3], c[1]};
  }
  for (int e0 = 0; e0 < 12; ++e0) {
    for (int e1 = 0; e1 < 12; ++e1) {
      // Edges share a face when a face holds all four end corners.
      const int c0 = edge_lower_corner(e0), c1 = edge_lower_corner(e1);
      const int ends[4] = {c0, c0 | (1 << (e0 / 4)), c1, c1 | (1 << (e1 / 4))};
      for (int f = 0; f < 6; ++f) {
        bool all = true;
        for (int c : ends) all = all && bit(c, f / 2) == f % 2;
        t.share_face[e0][e1] = t.share_face[e0][e1] || all;
      }
    }
  }
  t.loops.resize(256 * 64);
  for (int config = 0; config < 256; ++config) {
    for (int f = 0; f < 6; ++f) {
      const auto& c = t.local[f];
      const bool alternating = inside(config, c[0]) == inside(config, c[3]) &&
                               inside(config, c[1]) == inside(config, c[2]) &&
                               inside(config, c[0]) != inside(config, c[1]);
      if (alternating) t.ambiguous[config] |= static_cast<std::uint8_t>(1 << f);
    }
    for (int joined = 0; joined < 64; ++joined) {
      if ((joined & ~t.ambiguous[config]) != 0) continue;
      t.loops[config * 64 + joined] = make_loops(t, config, joined);
    }
  }
  return t;
}

const CubeTables& cube_tables() {
  static const CubeTables tables = make_tables();
  return tables;
}

// Where the crossing of edge (a, b) sits, a fraction of the way from a. Kept
// off the end nodes so that crossings of different edges never coincide (f
// exactly at the isovalue on a node would give zero-area faces).
double crossing_fraction(double ga, double gb) { return std::clamp(ga / (ga - gb), 1e-4, 1.0 - 1e-4); }

template <int N>
struct UnionFind {
  std::array<int, N> parent;
  UnionFind() {
    for (int i = 0; i < N; ++i) parent[i] = i;
  }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int a, int b) { parent[find(a)] = find(b); }
};

// Faces of a chunk of cells, and the vertices it adds inside cells; faces
// refer to those as -1 - (index in interior).
struct ChunkOutput {
  std::vector<Eigen::Vector3i> faces;
  std::vector<Eigen::Vector3f> interior, interior_normals;
};

// ---------------------------------------------------------------------------
// One cell. g holds the corner values minus the isovalue; corner 0 sits at
// origin, the cell's side is h.

class CellMesher {
 public:
  CellMesher(const CubeTables& t,
             const std::array<double, 8>& g,
             int config,
             const std::array<int, 12>& vertex,
             const Eigen::Vector3d& origin,
             double h,
             ChunkOutput& out)
      : t_(t), g_(g), config_(config), vertex_(vertex), origin_(origin), h_(h), out_(out) {}

  void run() {
    int joined = 0;
    for (int f = 0; f < 6; ++f) {
      if ((t_.ambiguous[config_] >> f) & 1 && inside_joined_on_face(f)) joined |= 1 << f;
    }
    const Loops& loops = t_.loops[config_ * 64 + joined];
    std::array<int, 4> start{};
    for (int l = 1; l < loops.count; ++l) start[l] = start[l - 1] + loops.length[l - 1];
    for (int n = 0; n < start[loops.count - 1] + loops.length[loops.count - 1]; ++n) {
      const int e = loops.edges[n];
      const int c0 = edge_lower_corner(e), c1 = c0 | (1 << (e / 4));
      pos_[e] = corner_position(c0) + crossing_fraction(g_[c0], g_[c1]) * (corner_position(c1) - corner_position(c0));
    }
    const auto [a, b] = loops.count >= 2 ? find_tunnel(loops, joined) : std::pair{-1, -1};
    if (a >= 0) stitch_tube(&loops.edges[start[a]], loops.length[a], &loops.edges[start[b]], loops.length[b]);
    for (int l = 0; l < loops.count; ++l) {
      if (l != a && l != b) triangulate_loop(&loops.edges[start[l]], loops.length[l]);
    }
  }

 private:
  static Eigen::Vector3d corner_position(int c) { return {double(bit(c, 0)), double(bit(c, 1)), double(bit(c, 2))}; }

  // Asymptotic decider: the bilinear interpolant on the face joins its
  // inside corners when its saddle value lies below the isovalue.
  bool inside_joined_on_face(int f) const {
    const auto& c = t_.local[f];
    const double a = g_[c[0]], b = g_[c[1]], cc = g_[c[2]], d = g_[c[3]];
    return (a * d - b * cc) / (a + d - b - cc) < 0.0;
  }

  // Lewiner's interior test, done as a sweep: slices z = t of the cell are
  // bilinear in (x, y) with corner values linear in t, so two columns
  // (vertical edges) holding the wanted side are joined inside the cell iff
  // in some slice they both hold it and the slice joins them, along a side
  // when adjacent, through the slice's saddle when diagonal. Returns the
  // union of columns.
  UnionFind<4> interior_columns(bool want_inside) const {
    std::array<std::pair<double, double>, 4> holds;  // t interval where column k is on the wanted side
    std::array<std::pair<double, double>, 4> other;
    for (int k = 0; k < 4; ++k) {
      const double a = g_[k], b = g_[k + 4];
      const bool ia = a < 0.0, ib = b < 0.0;
      std::pair<double, double> mine, theirs;
      if (ia == ib) {
        mine = ia == want_inside ? std::pair{0.0, 1.0} : std::pair{1.0, 0.0};
        theirs = ia == want_inside ? std::pair{1.0, 0.0} : std::pair{0.0, 1.0};
      } else {
        const double r = a / (a - b);
        const std::pair<double, double> low{0.0, r}, high{r, 1.0};
        mine = ia == want_inside ? low : high;
        theirs = ia == want_inside ? high : low;
      }
      holds[k] = mine;
      other[k] = theirs;
    }
    const auto overlap = [](std::pair<double, double> x, std::pair<double, double> y) {
      return std::pair{std::max(x.first, y.first), std::min(x.second, y.second)};
    };
    UnionFind<4> columns;
    for (const auto& [k, l] : {std::pair{0, 1}, std::pair{2, 3}, std::pair{0, 2}, std::pair{1, 3}}) {
      const auto span = overlap(holds[k], holds[l]);
      if (span.first <= span.second) columns.unite(k, l);
    }
    // Diagonal k, l with the other two on the other side: the saddle joins
    // columns 0 and 3 where D(t) = g0 g3 - g1 g2 > 0, columns 1 and 2 where D < 0.
    for (const auto& [k, l, m, n, side] : {std::tuple{0, 3, 1, 2, 1.0}, std::tuple{1, 2, 0, 3, -1.0}}) {
      const double sign = side;  // a lambda may not capture a structured binding before C++20
      const auto span = overlap(overlap(holds[k], holds[l]), overlap(other[m], other[n]));
      if (span.first > span.second) continue;
      const auto slope = [&](int c) { return g_[c + 4] - g_[c]; };
      const double c0 = g_[0] * g_[3] - g_[1] * g_[2];
      const double c1 = g_[0] * slope(3) + g_[3] * slope(0) - g_[1] * slope(2) - g_[2] * slope(1);
      const double c2 = slope(0) * slope(3) - slope(1) * slope(2);
      const auto d_at = [&](double t) { return sign * (c0 + t * (c1 + t * c2)); };
      double best = std::max(d_at(span.first), d_at(span.second));
      if (c2 != 0.0) {
        const double peak = -c1 / (2.0 * c2);
        if (peak > span.first && peak < span.second) best = std::max(best, d_at(peak));
      }
      // Strictly positive: where the span ends on a slice of zeros (the ghost
      // ring at the isovalue 0) D vanishes up to rounding.
      double scale = 0.0;
      for (double v : g_) scale = std::max(scale, v * v);
      if (best > 1e-9 * scale) columns.unite(k, l);
    }
    return columns;
  }

  // Two loops to stitch into a tube, or {-1, -1}. The cell's surface splits
  // the cube's boundary into regions; if the interior joins two regions of
  // the same side that the boundary keeps apart, the tube runs between the
  // two loops around them that border a common region of the other side.
  std::pair<int, int> find_tunnel(const Loops& loops, int joined) const {
    UnionFind<8> regions;
    for (int e = 0; e < 12; ++e) {
      const int c0 = edge_lower_corner(e), c1 = c0 | (1 << (e / 4));
      if (inside(config_, c0) == inside(config_, c1)) regions.unite(c0, c1);
    }
    for (int f = 0; f < 6; ++f) {
      if (!((t_.ambiguous[config_] >> f) & 1)) continue;
      const auto& c = t_.local[f];
      const bool diagonal_03_inside = inside(config_, c[0]);
      const bool join_03 = (((joined >> f) & 1) != 0) == diagonal_03_inside;
      if (join_03) {
        regions.unite(c[0], c[3]);
      } else {
        regions.unite(c[1], c[2]);
      }
    }
    // Each loop borders one inside and one outside region.
    std::array<std::pair<int, int>, 4> borders{};  // (inside region, outside region)
    for (int l = 0, n = 0; l < loops.count; n += loops.length[l++]) {
      const int e = loops.edges[n];
      const int c0 = edge_lower_corner(e), c1 = c0 | (1 << (e / 4));
      const bool in0 = inside(config_, c0);
      borders[l] = {regions.find(in0 ? c0 : c1), regions.find(in0 ? c1 : c0)};
    }
    for (const bool want_inside : {true, false}) {
      UnionFind<4> columns = interior_columns(want_inside);
      for (int c0 = 0; c0 < 8; ++c0) {
        for (int c1 = c0 + 1; c1 < 8; ++c1) {
          if (inside(config_, c0) != want_inside || inside(config_, c1) != want_inside) continue;
          const int r0 = regions.find(c0), r1 = regions.find(c1);
          if (r0 == r1 || columns.find(c0 & 3) != columns.find(c1 & 3)) continue;
          const auto mine = [&](int l) { return want_inside ? borders[l].first : borders[l].second; };
          const auto theirs = [&](int l) { return want_inside ? borders[l].second : borders[l].first; };
          for (int a = 0; a < loops.count; ++a) {
            for (int b = 0; b < loops.count; ++b) {
              if (a != b && mine(a) == r0 && mine(b) == r1 && theirs(a) == theirs(b)) return {a, b};
            }
          }
        }
      }
    }
    return {-1, -1};
  }

  // 1 for an equilateral triangle, 0 for a degenerate one.
  double quality(int e0, int e1, int e2) const {
    const Eigen::Vector3d &a = pos_[e0], &b = pos_[e1], &c = pos_[e2];
    const double sq = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
    return sq > 0.0 ? 2.0 * std::sqrt(3.0) * (b - a).cross(c - a).norm() / sq : 0.0;
  }

  void emit(int e0, int e1, int e2) { out_.faces.emplace_back(vertex_[e0], vertex_[e1], vertex_[e2]); }

  // f - isovalue and its gradient for the trilinear interpolant at p (cell coordinates).
  double trilinear(const Eigen::Vector3d& p, Eigen::Vector3d& gradient) const {
    double v = 0.0;
    gradient.setZero();
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d w(bit(c, 0) ? p.x() : 1.0 - p.x(), bit(c, 1) ? p.y() : 1.0 - p.y(),
                              bit(c, 2) ? p.z() : 1.0 - p.z());
      const Eigen::Vector3d dw(bit(c, 0) ? 1.0 : -1.0, bit(c, 1) ? 1.0 : -1.0, bit(c, 2) ? 1.0 : -1.0);
      v += g_[c] * w.prod();
      gradient += g_[c] * Eigen::Vector3d(dw.x() * w.y() * w.z(), w.x() * dw.y() * w.z(), w.x() * w.y() * dw.z());
    }
    return v;
  }

  // Adds a vertex inside the cell near p (cell coordinates), moved onto the
  // trilinear isosurface by Newton steps along the gradient; returns its id.
  int add_interior(Eigen::Vector3d p) {
    Eigen::Vector3d gradient;
    for (int step = 0; step < 4; ++step) {
      const double v = trilinear(p, gradient);
      if (!(gradient.squaredNorm() > 1e-24)) break;
      p = (p - v * gradient / gradient.squaredNorm()).cwiseMax(0.0).cwiseMin(1.0);
    }
    trilinear(p, gradient);
    const int id = -1 - static_cast<int>(out_.interior.size());
    out_.interior.push_back((origin_ + h_ * p).cast<float>());
    out_.interior_normals.push_back(gradient.norm() > 0.0 ? Eigen::Vector3f(gradient.normalized().cast<float>())
                                                          : Eigen::Vector3f::UnitZ());
    return id;
  }

  // Fans a loop around a vertex added inside the cell near its centroid.
  void fan_loop(const std::uint8_t* e, int n) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int i = 0; i < n; ++i) p += pos_[e[i]] / n;
    const int id = add_interior(p);
    for (int i = 0; i < n; ++i) out_.faces.emplace_back(vertex_[e[i]], vertex_[e[(i + 1) % n]], id);
  }

  // Triangulates a loop with the diagonals that maximise the smallest
  // triangle quality (then the sum). A diagonal between two crossings on one
  // cube face is not used: the neighbour across that face could pick it too,
  // giving an edge of four triangles. Loops that cannot avoid one (every
  // crossing on one of two opposite faces) are fanned around a new vertex.
  void triangulate_loop(const std::uint8_t* e, int n) {
    if (n == 3) {
      emit(e[0], e[1], e[2]);
      return;
    }
    struct Score {
      double min = -1.0, sum = 0.0;
      int split = -1;
    };
    std::array<std::array<Score, 12>, 12> best;
    const auto allowed = [&](int i, int j) {
      return j == i + 1 || (i == 0 && j == n - 1) || !t_.share_face[e[i]][e[j]];
    };
    for (int i = 0; i + 1 < n; ++i) best[i][i + 1] = Score{2.0, 0.0, -1};
    for (int len = 2; len < n; ++len) {
      for (int i = 0; i + len < n; ++i) {
        const int j = i + len;
        Score s;
        for (int k = i + 1; k < j; ++k) {
          if (!allowed(i, k) || !allowed(k, j) || best[i][k].min < 0.0 || best[k][j].min < 0.0) continue;
          const double q = quality(e[i], e[k], e[j]);
          const Score c{std::min({q, best[i][k].min, best[k][j].min}), q + best[i][k].sum + best[k][j].sum, k};
          if (c.min > s.min + 1e-12 || (c.min > s.min - 1e-12 && c.sum > s.sum)) s = c;
        }
        best[i][j] = s;
      }
    }
    if (best[0][n - 1].split < 0) {
      fan_loop(e, n);
      return;
    }
    std::array<std::pair<int, int>, 12> stack;
    int top = 0;
    stack[top++] = {0, n - 1};
    while (top > 0) {
      const auto [i, j] = stack[--top];
      if (j - i < 2) continue;
      const int k = best[i][j].split;
      emit(e[i], e[k], e[j]);
      stack[top++] = {i, k};
      stack[top++] = {k, j};
    }
  }

  // A tube between loops a and b: a band of triangles walking a forward and
  // b backward (so each loop keeps its direction and the tube its
  // orientation), with the rungs of least total length over all pairings of
  // the starts. Rungs between crossings on one cube face are not used (the
  // neighbour across the face could use the same edge); when the walk cannot
  // avoid them, every rung is split at a vertex added on the trilinear
  // isosurface near its midpoint, so no edge joins two crossings.
  void stitch_tube(const std::uint8_t* a, int na, const std::uint8_t* b, int nb) {
    // Walk (i, j) from (0, 0) to (na, nb) over rungs a[i mod na] - b[(s - j)
    // mod nb]. Rungs must not repeat: the walk starts along a, ends along b
    // and never visits (na, 0).
    constexpr double kBlocked = std::numeric_limits<double>::infinity();
    std::array<std::array<double, 13>, 13> cost;
    std::array<std::array<bool, 13>, 13> along_a;
    int s = 0;
    bool split = false;
    const auto b_at = [&](int j) { return b[((s - j) % nb + nb) % nb]; };
    const auto fill = [&] {
      for (int i = 0; i <= na; ++i) {
        for (int j = 0; j <= nb; ++j) {
          const int ea = a[i % na], eb = b_at(j);
          const bool blocked = (i == na && j == 0) || (!split && t_.share_face[ea][eb]);
          const double rung = blocked ? kBlocked : (pos_[ea] - pos_[eb]).norm();
          const double via_a = i > 0 && !(i == na && j == nb) ? cost[i - 1][j] : kBlocked;
          const double via_b = j > 0 && i > 0 ? cost[i][j - 1] : kBlocked;
          along_a[i][j] = via_a <= via_b;
          cost[i][j] = (i == 0 && j == 0 ? 0.0 : std::min(via_a, via_b)) + rung;
        }
      }
      return cost[na][nb];
    };
    int best_s = -1;
    for (const bool allow_split : {false, true}) {
      split = allow_split;
      double best = kBlocked;
      for (s = 0; s < nb; ++s) {
        const double c = fill();
        if (c < best) {
          best = c;
          best_s = s;
        }
      }
      if (best_s >= 0) break;
    }
    s = best_s;
    fill();
    std::array<std::pair<int, int>, 26> walk;  // rungs (i, j), first to last
    int len = 0;
    for (int i = na, j = nb;; along_a[i][j] ? --i : --j) {
      walk[len++] = {i, j};
      if (i == 0 && j == 0) break;
    }
    std::reverse(walk.begin(), walk.begin() + len);
    std::array<int, 26> middle{};  // split rungs' vertices; the last rung is the first
    if (split) {
      for (int r = 0; r + 1 < len; ++r) {
        const auto [i, j] = walk[r];
        middle[r] = add_interior(0.5 * (pos_[a[i % na]] + pos_[b_at(j)]));
      }
      middle[len - 1] = middle[0];
    }
    // Triangle u v w; split, with the rungs' vertices m_vw on edge v-w and
    // m_wu on edge w-u, into u v m_vw, u m_vw m_wu and m_vw w m_wu.
    const auto triangle = [&](int u, int v, int w, int m_vw, int m_wu) {
      if (!split) {
        out_.faces.emplace_back(u, v, w);
        return;
      }
      out_.faces.emplace_back(u, v, m_vw);
      out_.faces.emplace_back(u, m_vw, m_wu);
      out_.faces.emplace_back(m_vw, w, m_wu);
    };
    for (int r = 0; r + 1 < len; ++r) {
      const auto [i, j] = walk[r];
      const int m0 = middle[r], m1 = middle[r + 1];
      if (walk[r + 1].first > i) {
        // Triangle a_i a_i+1 b_j: rung r on edge b_j-a_i, rung r+1 on a_i+1-b_j.
        triangle(vertex_[a[i % na]], vertex_[a[(i + 1) % na]], vertex_[b_at(j)], m1, m0);
      } else {
        // Triangle b_j+1 b_j a_i: rung r on edge b_j-a_i, rung r+1 on a_i-b_j+1.
        triangle(vertex_[b_at(j + 1)], vertex_[b_at(j)], vertex_[a[i % na]], m0, m1);
      }
    }
  }

  const CubeTables& t_;
  const std::array<double, 8>& g_;
  int config_;
  const std::array<int, 12>& vertex_;
  Eigen::Vector3d origin_;
  double h_;
  ChunkOutput& out_;
  std::array<Eigen::Vector3d, 12> pos_;  // crossings in cell coordinates
};

// ---------------------------------------------------------------------------
// The grid, swept in chunks of z slabs. Node slab z holds the edges whose
// lower node has that z; its crossings are numbered in a fixed order after
// those of the slabs below, so every chunk finds the same vertex indices.

constexpr int kSlabsPerChunk = 4;

// The values a sweep reads: on every node (band null), or on the stored
// nodes of a band (values in its layout).
struct NodeSource {
  const std::vector<double>& values;
  const ActiveNodes* band;
};

class SlabSweep {
 public:
  // f: the grid's values (source.values on every node), or those of a band
  // (source.band): then only edges and cells whose nodes are all active are
  // used, and the ghost ring is never active.
  SlabSweep(const GridGeometry& g, const NodeSource& source, double iso)
      : g_(g), source_(source), iso_(iso), d_(g.dims) {
    px_ = d_.x() + 4;
    py_ = d_.y() + 4;
    for (auto& p : planes_) {
      p.values.assign(std::size_t(px_) * py_, 0.0);
      p.active.assign(std::size_t(px_) * py_, source_.band ? 0 : 1);
      p.row_active.assign(py_, source_.band ? 0 : 1);
    }
    for (auto& s : slabs_) s.index.assign(std::size_t(3) * (d_.x() + 2) * (d_.y() + 2), -1);
  }

  // f minus the isovalue at node (x, y, z); zero outside the ghost ring too.
  double value(int x, int y, int z) { return plane(z)[std::size_t(y + 2) * px_ + (x + 2)] - iso_; }

  // Numbers the crossings of node slab z from base on; returns how many.
  int index_slab(int z, int base) {
    Slab& s = slabs_[(z + 2) % 2];
    s.z = z;
    int n = base;
    const double* p0 = plane(z);
    const double* p1 = plane(z + 1);
    const std::uint8_t* a0 = active_plane(z);
    const std::uint8_t* a1 = active_plane(z + 1);
    // The crossings of node (x, y) of the slab, in the order they are numbered.
    const auto index_node = [&](int x, int y, std::size_t at) {
      const double* row = p0 + std::size_t(y + 2) * px_ + 2;
      const double* above = p1 + std::size_t(y + 2) * px_ + 2;
      const std::uint8_t* act = a0 + std::size_t(y + 2) * px_ + 2;
      const std::uint8_t* act_above = a1 + std::size_t(y + 2) * px_ + 2;
      const bool in = row[x] - iso_ < 0.0;
      const bool cross[3] = {x < d_.x() && act[x] && act[x + 1] && (row[x + 1] - iso_ < 0.0) != in,
                             y < d_.y() && act[x] && act[x + px_] && (row[x + px_] - iso_ < 0.0) != in,
                             z < d_.z() && act[x] && act_above[x] && (above[x] - iso_ < 0.0) != in};
      for (int a = 0; a < 3; ++a) s.index[at + a] = cross[a] ? n++ : -1;
    };
    if (source_.band) {
      // A crossing starts only at an active node: the active runs are
      // visited, and what the slab's last use wrote is reset first.
      for (const RowRange& w : s.written) {
        std::fill(s.index.begin() + slab_at(w.lo, w.y), s.index.begin() + slab_at(w.hi, w.y), -1);
      }
      s.written.clear();
      for (int y = 0; y < d_.y(); ++y) {
        const std::span<const NodeRun> runs = active_runs(y, z);
        if (runs.empty()) continue;
        for (const NodeRun& run : runs) {
          for (int x = run.begin; x < run.end; ++x) index_node(x, y, slab_at(x, y));
        }
        s.written.push_back({y, runs.front().begin, runs.back().end});
      }
      return n - base;
    }
    for (int y = -1; y <= d_.y(); ++y) {
      for (int x = -1; x <= d_.x(); ++x) index_node(x, y, slab_at(x, y));
    }
    return n - base;
  }

  int vertex(int x, int y, int z, int axis) const {
    const Slab& s = slabs_[(z + 2) % 2];
    return s.index[slab_at(x, y) + axis];
  }

  // Writes the positions and gradient normals of node slab z's crossings
  // (numbered by index_slab just before).
  void write_slab(int z, TriangleMesh& mesh, std::vector<GridEdge>* edges) {
    const GridGeometry& g = g_;
    const auto write_node = [&](int x, int y) {
      for (int a = 0; a < 3; ++a) {
        const int v = vertex(x, y, z, a);
        if (v < 0) continue;
        const Eigen::Vector3i n0(x, y, z);
        const Eigen::Vector3i n1 = n0 + Eigen::Vector3i::Unit(a);
        const double g0 = value(x, y, z), g1 = value(n1.x(), n1.y(), n1.z());
        const double t = crossing_fraction(g0, g1);
        mesh.vertices[v] = (g.position(x, y, z) + t * g.spacing * Eigen::Vector3d::Unit(a)).cast<float>();
        Eigen::Vector3d normal = (1.0 - t) * gradient(n0) + t * gradient(n1);
        if (!(normal.norm() > 0.0)) normal = (g1 > g0 ? 1.0 : -1.0) * Eigen::Vector3d::Unit(a);
        mesh.normals[v] = normal.normalized().cast<float>();
        if (edges) (*edges)[v] = GridEdge{n0, a};
      }
    };
    load(z);
    if (source_.band) {
      for (int y = 0; y < d_.y(); ++y) {
        for (const NodeRun& run : active_runs(y, z)) {
          for (int x = run.begin; x < run.end; ++x) write_node(x, y);
        }
      }
      return;
    }
    for (int y = -1; y <= d_.y(); ++y) {
      for (int x = -1; x <= d_.x(); ++x) write_node(x, y);
    }
  }

  // Meshes the cells of slab k (lower corners at z = k); needs node slabs k
  // and k + 1 indexed.
  void mesh_cells(int k, ChunkOutput& out) {
    const CubeTables& t = cube_tables();
    std::array<double, 8> g;
    std::array<int, 12> vertex{};
    const std::array<const double*, 2> planes = {plane(k), plane(k + 1)};
    const std::array<const std::uint8_t*, 2> actives = {active_plane(k), active_plane(k + 1)};
    const std::array<const std::uint8_t*, 2> rows_in_use = {load(k).row_active.data(), load(k + 1).row_active.data()};
    for (int y = -1; y < d_.y(); ++y) {
      if (!(rows_in_use[0][y + 2] && rows_in_use[0][y + 3] && rows_in_use[1][y + 2] && rows_in_use[1][y + 3])) continue;
      std::array<const double*, 4> rows;  // corners' rows by (y bit, z bit)
      std::array<const std::uint8_t*, 4> active_rows;
      for (int c = 0; c < 4; ++c) {
        rows[c] = planes[c >> 1] + std::size_t(y + 2 + (c & 1)) * px_ + 2;
        active_rows[c] = actives[c >> 1] + std::size_t(y + 2 + (c & 1)) * px_ + 2;
      }
      const auto mesh_cell = [&](int x) {
        int config = 0;
        for (int c = 0; c < 8; ++c) {
          g[c] = rows[c >> 1][x + (c & 1)] - iso_;
          config |= int(g[c] < 0.0) << c;
        }
        if (config == 0 || config == 255) return;
        for (int e = 0; e < 12; ++e) {
          const int c0 = edge_lower_corner(e);
          vertex[e] = this->vertex(x + bit(c0, 0), y + bit(c0, 1), k + bit(c0, 2), e / 4);
        }
        CellMesher(t, g, config, vertex, g_.position(x, y, k), g_.spacing, out).run();
      };
      if (!source_.band) {
        for (int x = -1; x < d_.x(); ++x) mesh_cell(x);
        continue;
      }
      // A cell is meshed when its eight corners are active: its lower corner
      // lies in an active run of row (y, k), with its x neighbour.
      for (const NodeRun& run : active_runs(y, k)) {
        for (int x = run.begin; x + 1 < run.end; ++x) {
          bool all = true;
          for (int c = 0; c < 4 && all; ++c) all = active_rows[c][x] && active_rows[c][x + 1];
          if (all) mesh_cell(x);
        }
      }
    }
  }

 private:
  // The nodes lo <= x < hi of row y of a plane or slab that a band's load
  // wrote, reset by the next.
  struct RowRange {
    int y, lo, hi;
  };
  struct Plane {
    int z = std::numeric_limits<int>::min();
    std::vector<double> values;            // nodes -2 .. dims, x fastest
    std::vector<std::uint8_t> active;      // the same nodes: may the node be used?
    std::vector<std::uint8_t> row_active;  // per row y + 2: has it an active node?
    std::vector<RowRange> written;         // band: the stored nodes' rows
  };
  struct Slab {
    int z = std::numeric_limits<int>::min();
    std::vector<int> index;         // vertex per (node, axis), -1 without a crossing
    std::vector<RowRange> written;  // band: the rows indexed
  };

  // Index in Slab::index of node (x, y)'s first axis.
  std::size_t slab_at(int x, int y) const { return (std::size_t(y + 1) * (d_.x() + 2) + (x + 1)) * 3; }

  // The band's active runs of row y of plane z (none outside the grid).
  std::span<const NodeRun> active_runs(int y, int z) const {
    if (y < 0 || z < 0 || y >= d_.y() || z >= d_.z()) return {};
    const RowRuns& set = source_.band->active_set();
    const std::int64_t row = std::int64_t{z} * d_.y() + y;
    return {set.runs.data() + set.row_begin[row], set.runs.data() + set.row_begin[row + 1]};
  }

  Plane& load(int z) {
    Plane& p = planes_[(z + 4) % 4];  // z >= -2: four consecutive slabs never collide
    if (p.z == z) return p;
    p.z = z;
    if (source_.band) {
      load_band(z, p);
      return p;
    }
    std::fill(p.values.begin(), p.values.end(), 0.0);
    if (z < 0 || z >= d_.z()) return p;
    for (int y = 0; y < d_.y(); ++y) {
      const double* row = &source_.values[g_.index(0, y, z)];
      std::copy(row, row + d_.x(), &p.values[std::size_t(y + 2) * px_ + 2]);
    }
    return p;
  }

  // A band's plane: its stored values (zero elsewhere) and active nodes.
  // Only the rows the plane's last use wrote are cleared: a band stores a
  // few percent of a large grid's nodes, and clearing whole planes cost more
  // than meshing them.
  void load_band(int z, Plane& p) {
    for (const RowRange& w : p.written) {
      const std::size_t at = std::size_t(w.y + 2) * px_ + 2;
      std::fill(p.values.begin() + at + w.lo, p.values.begin() + at + w.hi, 0.0);
      std::fill(p.active.begin() + at + w.lo, p.active.begin() + at + w.hi, 0);
    }
    p.written.clear();
    std::fill(p.row_active.begin(), p.row_active.end(), 0);
    if (z < 0 || z >= d_.z()) return;
    const ActiveNodes& band = *source_.band;
    for (int y = 0; y < d_.y(); ++y) {
      const std::size_t at = std::size_t(y + 2) * px_ + 2;
      int lo = d_.x(), hi = 0;
      band.for_each_stored_run(std::int64_t{z} * d_.y() + y, [&](int a, int b, std::int64_t base) {
        std::copy(source_.values.begin() + base + a, source_.values.begin() + base + b, p.values.begin() + at + a);
        lo = std::min(lo, a);
        hi = std::max(hi, b);
      });
      if (lo < hi) p.written.push_back({y, lo, hi});
      const std::span<const NodeRun> runs = active_runs(y, z);
      p.row_active[y + 2] = !runs.empty();
      for (const NodeRun& run : runs) std::fill(p.active.begin() + at + run.begin, p.active.begin() + at + run.end, 1);
    }
  }
  const double* plane(int z) { return load(z).values.data(); }
  const std::uint8_t* active_plane(int z) { return load(z).active.data(); }

  // Central differences (one-sided nowhere: f is zero beyond the ghost ring).
  Eigen::Vector3d gradient(const Eigen::Vector3i& n) {
    const int x = n.x(), y = n.y(), z = n.z();
    return Eigen::Vector3d(value(x + 1, y, z) - value(x - 1, y, z), value(x, y + 1, z) - value(x, y - 1, z),
                           value(x, y, z + 1) - value(x, y, z - 1)) /
           (2.0 * g_.spacing);
  }

  const GridGeometry& g_;
  const NodeSource& source_;
  double iso_;
  Eigen::Vector3i d_;
  int px_ = 0, py_ = 0;
  std::array<Plane, 4> planes_;
  std::array<Slab, 2> slabs_;
};

}  // namespace

namespace {

// edges (optional) receives every vertex's grid edge.
TriangleMesh extract(const GridGeometry& geometry,
                     const NodeSource& source,
                     double isovalue,
                     std::vector<GridEdge>* edges = nullptr) {
  const Eigen::Vector3i d = geometry.dims;
  TriangleMesh mesh;
  if ((d.array() <= 0).any()) return mesh;
  cube_tables();  // built once, before the threads need it
  // Cell slabs k = -1 .. dims.z - 1 in chunks; node slabs -1 .. dims.z.
  const int cell_slabs = d.z() + 1;
  const int chunks = (cell_slabs + kSlabsPerChunk - 1) / kSlabsPerChunk;
  const auto chunk_begin = [&](int c) { return -1 + c * kSlabsPerChunk; };
  const auto chunk_end = [&](int c) { return std::min(d.z(), chunk_begin(c) + kSlabsPerChunk); };
  const bool threads = worth_threads(geometry.num_nodes());

  // Pass 1: crossings per node slab, then each slab's first vertex index.
  std::vector<int> first(std::size_t(d.z()) + 3, 0);  // [z + 1], one past the top
#pragma omp parallel if (threads)
  {
    SlabSweep sweep(geometry, source, isovalue);
#pragma omp for schedule(dynamic, 1)
    for (int c = 0; c < chunks; ++c) {
      for (int z = chunk_begin(c); z < chunk_end(c); ++z) first[z + 2] = sweep.index_slab(z, 0);
      if (chunk_end(c) == d.z()) first[d.z() + 2] = sweep.index_slab(d.z(), 0);
    }
  }
  for (std::size_t z = 1; z < first.size(); ++z) first[z] += first[z - 1];
  mesh.vertices.resize(first.back());
  mesh.normals.resize(first.back());
  if (edges) edges->assign(first.back(), GridEdge{});

  // Pass 2: vertices of each chunk's node slabs, faces of its cell slabs.
  std::vector<ChunkOutput> out(chunks);
#pragma omp parallel if (threads)
  {
    SlabSweep sweep(geometry, source, isovalue);
#pragma omp for schedule(dynamic, 1)
    for (int c = 0; c < chunks; ++c) {
      sweep.index_slab(chunk_begin(c), first[chunk_begin(c) + 1]);
      for (int k = chunk_begin(c); k < chunk_end(c); ++k) {
        sweep.write_slab(k, mesh, edges);
        sweep.index_slab(k + 1, first[k + 2]);
        if (k + 1 == d.z()) sweep.write_slab(k + 1, mesh, edges);
        sweep.mesh_cells(k, out[c]);
      }
    }
  }
  // Vertices added inside cells go after the edge crossings, chunk by chunk.
  std::size_t total = 0;
  for (const auto& part : out) total += part.faces.size();
  mesh.faces.reserve(total);
  for (auto& part : out) {
    const int base = static_cast<int>(mesh.vertices.size());
    for (Eigen::Vector3i face : part.faces) {
      for (int c = 0; c < 3; ++c) face[c] = face[c] < 0 ? base - 1 - face[c] : face[c];
      mesh.faces.push_back(face);
    }
    mesh.vertices.insert(mesh.vertices.end(), part.interior.begin(), part.interior.end());
    mesh.normals.insert(mesh.normals.end(), part.interior_normals.begin(), part.interior_normals.end());
    if (edges) edges->resize(mesh.vertices.size(), GridEdge{});
  }
  return mesh;
}

}  // namespace

TriangleMesh extract_isosurface(const ScalarGrid& f, double isovalue) {
  return extract(f.geometry, NodeSource{f.values, nullptr}, isovalue);
}

TriangleMesh extract_isosurface(const GridGeometry& g, const StoredField& f, double isovalue) {
  if (f.nodes->is_all()) return extract(g, NodeSource{f.values, nullptr}, isovalue);
  TriangleMesh mesh = extract(g, NodeSource{f.values, f.nodes.get()}, isovalue);
  remove_unreferenced_vertices(mesh);
  return mesh;
}

TriangleMesh extract_isosurface(const GridGeometry& g,
                                const StoredField& f,
                                double isovalue,
                                std::vector<GridEdge>& vertex_edges) {
  TriangleMesh mesh =
      extract(g, NodeSource{f.values, f.nodes->is_all() ? nullptr : f.nodes.get()}, isovalue, &vertex_edges);
  const std::vector<int> remap = remove_unreferenced_vertices(mesh);
  std::vector<GridEdge> kept(mesh.vertices.size());
  for (std::size_t i = 0; i < remap.size(); ++i) {
    if (remap[i] >= 0) kept[remap[i]] = vertex_edges[i];
  }
  vertex_edges.swap(kept);
  return mesh;
}

}  // namespace hos::recon
