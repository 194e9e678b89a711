#include "texture/unseen_faces.h"

#include <algorithm>
#include <optional>

namespace hos::texture {
namespace {

// The candidate of face f from the view it is textured from (nullptr if none).
const FaceViewSample* selected_sample(const FaceViewCandidates& candidates, int f, int view) {
  for (int k = candidates.begin(f); k < candidates.end(f); ++k) {
    if (candidates.samples[k].view == view) return &candidates.samples[k];
  }
  return nullptr;
}

enum class Fill : char { kNone, kSource, kFilled };

// The mean colour of f's neighbours that have one (sources and filled faces);
// nothing when none has.
std::optional<Eigen::Vector3f> mean_coloured_neighbour(const MeshTopology& topology,
                                                       const std::vector<Fill>& state,
                                                       const std::vector<Eigen::Vector3f>& colour,
                                                       int f) {
  Eigen::Vector3f sum = Eigen::Vector3f::Zero();
  int n = 0;
  for (int g : topology.face_neighbors[f]) {
    if (g >= 0 && state[g] != Fill::kNone) {
      sum += colour[g];
      ++n;
    }
  }
  if (n == 0) return std::nullopt;
  return Eigen::Vector3f(sum / static_cast<float>(n));
}

// Ring by ring from the sources through faces without a colour: each face
// reached takes the mean of its neighbours reached before it. The start of
// the harmonic fill, and what decides which faces the sources reach.
void propagate_from_sources(const MeshTopology& topology,
                            std::vector<Fill>& state,
                            std::vector<Eigen::Vector3f>& colour) {
  const int num_faces = static_cast<int>(state.size());
  std::vector<int> front;
  for (int f = 0; f < num_faces; ++f) {
    if (state[f] != Fill::kNone) continue;
    for (int g : topology.face_neighbors[f]) {
      if (g >= 0 && state[g] != Fill::kNone) {
        front.push_back(f);
        break;
      }
    }
  }
  std::vector<int> next;
  std::vector<std::pair<int, Eigen::Vector3f>> updates;
  while (!front.empty()) {
    updates.clear();
    for (int f : front) {
      if (const auto mean = mean_coloured_neighbour(topology, state, colour, f)) updates.emplace_back(f, *mean);
    }
    next.clear();
    for (const auto& [f, c] : updates) {
      if (state[f] != Fill::kNone) continue;
      state[f] = Fill::kFilled;
      colour[f] = c;
      for (int g : topology.face_neighbors[f]) {
        if (g >= 0 && state[g] == Fill::kNone) next.push_back(g);
      }
    }
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    front.swap(next);
  }
}

// Gauss-Seidel sweeps of the harmonic fill: every filled face becomes the
// mean of its coloured neighbours, until no colour moves by more than
// kTolerance (8-bit units) or after kMaxSweeps.
void relax_filled_faces(const MeshTopology& topology,
                        const std::vector<Fill>& state,
                        std::vector<Eigen::Vector3f>& colour) {
  constexpr float kTolerance = 0.25f;
  constexpr int kMaxSweeps = 200;
  std::vector<int> filled;
  for (int f = 0; f < static_cast<int>(state.size()); ++f) {
    if (state[f] == Fill::kFilled) filled.push_back(f);
  }
  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    float largest_change = 0.0f;
    for (int f : filled) {
      // Every filled face has a coloured neighbour: it was reached from one.
      const Eigen::Vector3f mean = *mean_coloured_neighbour(topology, state, colour, f);
      largest_change = std::max(largest_change, (mean - colour[f]).cwiseAbs().maxCoeff());
      colour[f] = mean;
    }
    if (largest_change < kTolerance) break;
  }
}

// The harmonic fill with the given sources; faces the sources do not reach
// stay Fill::kNone.
std::vector<Fill> diffuse_from(const MeshTopology& topology,
                               const std::vector<char>& is_source,
                               const std::vector<Eigen::Vector3f>& seen_colours,
                               std::vector<Eigen::Vector3f>& colour) {
  std::vector<Fill> state(is_source.size(), Fill::kNone);
  for (std::size_t f = 0; f < is_source.size(); ++f) {
    if (!is_source[f]) continue;
    state[f] = Fill::kSource;
    colour[f] = seen_colours[f];
  }
  propagate_from_sources(topology, state, colour);
  relax_filled_faces(topology, state, colour);
  return state;
}

// The faces within `rings` edge-steps of face f (f included) that pass keep;
// mark holds stamp for the faces found.
template <typename Keep>
std::vector<int> faces_within(
    const MeshTopology& topology, int f, int rings, Keep&& keep, std::vector<int>& mark, int stamp) {
  std::vector<int> found{f}, front{f};
  mark[f] = stamp;
  for (int ring = 0; ring < rings && !front.empty(); ++ring) {
    std::vector<int> next;
    for (int a : front) {
      for (int b : topology.face_neighbors[a]) {
        if (b < 0 || mark[b] == stamp || !keep(b)) continue;
        mark[b] = stamp;
        next.push_back(b);
        found.push_back(b);
      }
    }
    front.swap(next);
  }
  return found;
}

// The colours the diffusion starts from: each source face that borders a
// face to fill takes the colour of median brightness among the sources
// within kMedianRings of it. Along the edge of what the photos see, the
// surface often reaches a little past the true object (its underside closed
// by the reconstruction), and those faces show the background: a quarter of
// the faces bordering the unseen underside of hos-synth's scene are near
// black, fewer farther up. A median over a few rings keeps the surface's
// colour where such faces are a minority.
std::vector<Eigen::Vector3f> robust_source_colours(const MeshTopology& topology,
                                                   const std::vector<char>& is_source,
                                                   const std::vector<Eigen::Vector3f>& seen_colours) {
  constexpr int kMedianRings = 3;
  const int num_faces = static_cast<int>(is_source.size());
  std::vector<Eigen::Vector3f> robust = seen_colours;
  std::vector<int> mark(num_faces, -1);
  const auto source = [&](int g) { return is_source[g] != 0; };
  const auto brightness = [&](int g) { return seen_colours[g].sum(); };
  for (int f = 0; f < num_faces; ++f) {
    if (!is_source[f]) continue;
    bool borders_fill = false;
    for (int g : topology.face_neighbors[f]) borders_fill |= g >= 0 && !is_source[g];
    if (!borders_fill) continue;
    std::vector<int> near = faces_within(topology, f, kMedianRings, source, mark, f);
    std::nth_element(near.begin(), near.begin() + near.size() / 2, near.end(),
                     [&](int a, int b) { return brightness(a) < brightness(b); });
    robust[f] = seen_colours[near[near.size() / 2]];
  }
  return robust;
}

}  // namespace

std::vector<Eigen::Vector3f> seen_face_colours(const FaceViewCandidates& candidates,
                                               const std::vector<int>& labels,
                                               const std::vector<Chart>& charts,
                                               const SeamLeveling& leveling) {
  std::vector<Eigen::Vector3f> colour(labels.size(), Eigen::Vector3f::Zero());
  for (std::size_t c = 0; c < charts.size(); ++c) {
    const bool leveled = c < leveling.offsets.size() && !leveling.offsets[c].empty();
    for (std::size_t i = 0; i < charts[c].faces.size(); ++i) {
      const int f = charts[c].faces[i];
      const FaceViewSample* sample = selected_sample(candidates, f, charts[c].view);
      if (!sample) continue;
      Eigen::Vector3f offset = Eigen::Vector3f::Zero();
      if (leveled) {
        for (int k = 0; k < 3; ++k) offset += leveling.offsets[c][charts[c].local_faces[i][k]];
        offset /= 3.0f;
      }
      colour[f] = (sample->mean_rgb + offset).cwiseMax(0.0f).cwiseMin(255.0f);
    }
  }
  return colour;
}

const char* unseen_faces_description(UnseenFaces mode) {
  switch (mode) {
    case UnseenFaces::kDiffuse:
      return "the colours of the seen faces around them, diffused over the surface";
    case UnseenFaces::kGrey:
      return "grey";
    case UnseenFaces::kMark:
      return "magenta (texture.unseen=mark)";
  }
  return "";
}

std::vector<std::optional<Eigen::Vector3f>> uniform_backgrounds(const std::vector<TextureView>& views,
                                                                const std::vector<Eigen::Vector3f>& gains) {
  std::vector<std::optional<Eigen::Vector3f>> backgrounds(views.size());
  for (std::size_t v = 0; v < views.size(); ++v) {
    const cv::Mat& image = views[v].image;
    if (image.empty() || image.type() != CV_8UC3) continue;
    std::vector<Eigen::Vector3f> border;
    const auto add = [&](int x, int y) {
      const cv::Vec3b& p = image.at<cv::Vec3b>(y, x);
      border.emplace_back(p[2], p[1], p[0]);
    };
    // A rectangle 2% inside the frame: undistorted photos may have blank margins.
    const int inset = std::min(image.cols, image.rows) / 50;
    const int x0 = inset, x1 = image.cols - 1 - inset, y0 = inset, y1 = image.rows - 1 - inset;
    if (x1 <= x0 || y1 <= y0) continue;
    for (int x = x0; x <= x1; ++x) {
      add(x, y0);
      add(x, y1);
    }
    for (int y = y0 + 1; y < y1; ++y) {
      add(x0, y);
      add(x1, y);
    }
    Eigen::Vector3f median;
    for (int c = 0; c < 3; ++c) {
      std::vector<float> channel(border.size());
      for (std::size_t i = 0; i < border.size(); ++i) channel[i] = border[i][c];
      std::nth_element(channel.begin(), channel.begin() + channel.size() / 2, channel.end());
      median[c] = channel[channel.size() / 2];
    }
    const auto close = std::count_if(border.begin(), border.end(), [&](const Eigen::Vector3f& p) {
      return (p - median).norm() < kBackgroundDistance;
    });
    const Eigen::Vector3f gain = v < gains.size() ? gains[v] : Eigen::Vector3f::Ones();
    if (close >= kUniformBorderShare * static_cast<double>(border.size())) backgrounds[v] = gain.cwiseProduct(median);
  }
  return backgrounds;
}

std::vector<FlatFace> colour_unseen_faces(const MeshTopology& topology,
                                          const FaceViewCandidates& candidates,
                                          const std::vector<int>& labels,
                                          const std::vector<Eigen::Vector3f>& seen_colours,
                                          const std::vector<std::optional<Eigen::Vector3f>>& backgrounds,
                                          UnseenFaces mode) {
  std::vector<FlatFace> flat;
  const int num_faces = static_cast<int>(labels.size());
  for (int f = 0; f < num_faces; ++f) {
    if (labels[f] < 0) flat.push_back({f, Eigen::Vector3f::Constant(kUnseenGrey)});
  }
  if (flat.empty() || mode == UnseenFaces::kGrey) return flat;
  if (mode == UnseenFaces::kMark) {
    for (FlatFace& face : flat) face.rgb = Eigen::Vector3f(255.0f, 0.0f, 255.0f);
    return flat;
  }
  // Sources: seen faces viewed well; then, for unseen regions only grazing
  // views border, every seen face; never a face showing the background.
  std::vector<char> well_seen(num_faces, 0), seen(num_faces, 0);
  for (int f = 0; f < num_faces; ++f) {
    if (labels[f] < 0) continue;
    const FaceViewSample* sample = selected_sample(candidates, f, labels[f]);
    const bool background = sample && sample->view < static_cast<int>(backgrounds.size()) &&
                            backgrounds[sample->view] &&
                            (sample->mean_rgb - *backgrounds[sample->view]).norm() < kBackgroundDistance;
    seen[f] = !background;
    well_seen[f] = sample && sample->cos_angle >= kMinSourceCosine && !background;
  }
  std::vector<Eigen::Vector3f> colour(num_faces, Eigen::Vector3f::Zero());
  const std::vector<Fill> state =
      diffuse_from(topology, well_seen, robust_source_colours(topology, well_seen, seen_colours), colour);
  std::vector<Eigen::Vector3f> fallback_colour;
  std::vector<Fill> fallback_state;
  for (FlatFace& face : flat) {
    if (state[face.face] != Fill::kNone) {
      face.rgb = colour[face.face];
      continue;
    }
    if (fallback_state.empty()) {
      fallback_colour.assign(num_faces, Eigen::Vector3f::Zero());
      fallback_state =
          diffuse_from(topology, seen, robust_source_colours(topology, seen, seen_colours), fallback_colour);
    }
    // A piece no view sees at all keeps the neutral grey.
    if (fallback_state[face.face] != Fill::kNone) face.rgb = fallback_colour[face.face];
  }
  return flat;
}

}  // namespace hos::texture
