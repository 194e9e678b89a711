#include "texture/atlas.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <opencv2/imgproc.hpp>

#include "render/scan_triangle.h"
#include "texture/atlas_packing.h"

namespace hos::texture {

namespace {

constexpr int kFlatCell = 1;        // texels per side of a flat face's patch (sampled at its centre)
constexpr int kFlatColourStep = 4;  // flat colours this close (8-bit) share a patch

// A chart's map from its view's photo pixels to page texels (texel = linear *
// pixel + offset; a rotation, scale and translation, so texels are resampled
// once from the photo) and its footprint while packing.
struct ChartFrame {
  std::vector<Eigen::Vector2d> pixels;                        // projected chart vertices, photo pixels
  Eigen::Matrix2d orientation = Eigen::Matrix2d::Identity();  // turns the minimum-area rectangle onto the axes
  double scale = 1.0;                                         // texels per photo pixel
  Eigen::Matrix2d linear = Eigen::Matrix2d::Identity();
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();
};

// Calls fill(x, y, barycentric) for each texel whose centre lies in the
// triangle (texel coordinates; centres on an edge count for both faces).
template <typename Fill>
void raster_triangle(
    const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c, int width, int height, Fill&& fill) {
  const double area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
  if (std::abs(area) < 1e-12) return;
  const render::PixelRange range{std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}) - 0.5))),
                                 std::min(width - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()})))),
                                 std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}) - 0.5))),
                                 std::min(height - 1, static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))))};
  render::scan_triangle(
      a, b, c, 1.0 / area, range,
      [&](int x, int y, double wa, double wb, double wc) { fill(x, y, Eigen::Vector3d(wa, wb, wc)); }, -1e-6);
}

// Fills empty texels from filled 8-neighbours, ring by ring.
void dilate(cv::Mat& page, cv::Mat& filled, int rings) {
  for (int ring = 0; ring < rings; ++ring) {
    cv::Mat next_filled = filled.clone();
    for (int y = 0; y < page.rows; ++y) {
      for (int x = 0; x < page.cols; ++x) {
        if (filled.at<std::uint8_t>(y, x)) continue;
        Eigen::Vector3i sum = Eigen::Vector3i::Zero();
        int count = 0;
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if (xx < 0 || yy < 0 || xx >= page.cols || yy >= page.rows) continue;
            if (!filled.at<std::uint8_t>(yy, xx)) continue;
            const cv::Vec3b& p = page.at<cv::Vec3b>(yy, xx);
            sum += Eigen::Vector3i(p[0], p[1], p[2]);
            ++count;
          }
        }
        if (count == 0) continue;
        page.at<cv::Vec3b>(y, x) = cv::Vec3b(sum[0] / count, sum[1] / count, sum[2] / count);
        next_filled.at<std::uint8_t>(y, x) = 255;
      }
    }
    filled = next_filled;
  }
}

cv::Vec3b to_bgr(const Eigen::Vector3f& rgb) {
  auto clamp8 = [](float v) { return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L)); };
  return cv::Vec3b(clamp8(rgb.z()), clamp8(rgb.y()), clamp8(rgb.x()));
}

// The rotation that turns the points' minimum-area bounding rectangle onto
// the axes (of the two candidate angles, the one with the smaller box).
Eigen::Matrix2d minimum_area_orientation(const std::vector<Eigen::Vector2d>& points) {
  if (points.size() < 3) return Eigen::Matrix2d::Identity();
  std::vector<cv::Point2f> cv_points;
  cv_points.reserve(points.size());
  for (const auto& p : points) cv_points.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  const double angle = cv::minAreaRect(cv_points).angle * M_PI / 180.0;
  Eigen::Matrix2d best = Eigen::Matrix2d::Identity();
  double best_area = std::numeric_limits<double>::max();
  for (const double a : {0.0, angle, -angle}) {
    Eigen::Matrix2d r;
    r << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = Eigen::Vector2d::Constant(-1e300);
    for (const auto& p : points) {
      lo = lo.cwiseMin(r * p);
      hi = hi.cwiseMax(r * p);
    }
    const double area = (hi - lo).prod();
    if (area < best_area * 0.999) {  // the axes unless a turn is clearly better
      best_area = area;
      best = r;
    }
  }
  return best;
}

// Every chart's vertices projected into its view (photo pixels) and the
// orientation of its minimum-area rectangle.
std::vector<ChartFrame> project_charts(const TriangleMesh& mesh,
                                       const std::vector<Chart>& charts,
                                       const std::vector<TextureView>& views) {
  std::vector<ChartFrame> frames(charts.size());
  for (std::size_t c = 0; c < charts.size(); ++c) {
    ChartFrame& frame = frames[c];
    const TextureView& view = views[charts[c].view];
    frame.pixels.resize(charts[c].vertices.size());
    for (std::size_t i = 0; i < charts[c].vertices.size(); ++i) {
      frame.pixels[i] = view.project(mesh.vertices[charts[c].vertices[i]].cast<double>()).head<2>();
    }
    frame.orientation = minimum_area_orientation(frame.pixels);
  }
  return frames;
}

// The distinct colours of the faces no view sees (rounded to
// kFlatColourStep), one patch each, in one block of patches.
struct FlatPatches {
  std::vector<cv::Vec3b> colours;
  std::vector<int> patch_of;  // per flat face
  int columns = 0, rows = 0;  // of the block, in patches
};

FlatPatches flat_patches(const std::vector<FlatFace>& flat_faces) {
  FlatPatches out;
  std::map<std::array<int, 3>, int> index;
  for (const FlatFace& face : flat_faces) {
    const cv::Vec3b bgr = to_bgr(face.rgb);
    std::array<int, 3> key;
    cv::Vec3b rounded;
    for (int k = 0; k < 3; ++k) {
      key[k] = (bgr[k] + kFlatColourStep / 2) / kFlatColourStep;
      rounded[k] = static_cast<std::uint8_t>(std::min(255, key[k] * kFlatColourStep));
    }
    const auto [it, inserted] = index.emplace(key, static_cast<int>(out.colours.size()));
    if (inserted) out.colours.push_back(rounded);
    out.patch_of.push_back(it->second);
  }
  const int n = static_cast<int>(out.colours.size());
  out.columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
  out.rows = out.columns > 0 ? (n + out.columns - 1) / out.columns : 0;
  return out;
}

// Where every chart (first) and the block of flat patches (last, if any) goes.
struct Packing {
  std::vector<FootprintPlacement> placements;
  std::vector<cv::Size> footprint_sizes;  // before the turn
  int num_pages = 0;
  int page_width = 0;
  double scale = 1.0;  // texels per photo pixel
};

// The chart at scale s in its own footprint: sets frame.scale and the map
// into the footprint's texels (before the turn and the placement) and returns
// the footprint, the texels whose centres the chart covers, cropped to their
// bounding box (the packer keeps the padding between footprints).
cv::Mat chart_footprint(const Chart& chart, ChartFrame& frame, double s, int page_size) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = Eigen::Vector2d::Constant(-1e300);
  for (const auto& p : frame.pixels) {
    lo = lo.cwiseMin(frame.orientation * p);
    hi = hi.cwiseMax(frame.orientation * p);
  }
  const Eigen::Vector2d extent = hi - lo;
  const int margin = 1;
  // A chart wider than a page is scaled down on its own.
  const double limit = page_size - 2 * margin - 2;
  if (extent.maxCoeff() * s > limit) s = limit / extent.maxCoeff();
  frame.scale = s;
  frame.linear = s * frame.orientation;
  frame.offset = -s * lo + Eigen::Vector2d::Constant(margin);
  cv::Mat mask(static_cast<int>(std::ceil(extent.y() * s)) + 2 * margin + 1,
               static_cast<int>(std::ceil(extent.x() * s)) + 2 * margin + 1, CV_8U, cv::Scalar(0));
  std::vector<Eigen::Vector2d> texel(frame.pixels.size());
  for (std::size_t i = 0; i < texel.size(); ++i) texel[i] = frame.linear * frame.pixels[i] + frame.offset;
  for (const auto& face : chart.local_faces) {
    raster_triangle(texel[face[0]], texel[face[1]], texel[face[2]], mask.cols, mask.rows,
                    [&](int x, int y, const Eigen::Vector3d&) { mask.at<std::uint8_t>(y, x) = 255; });
  }
  const cv::Rect box = cv::boundingRect(mask);
  if (box.area() == 0) return cv::Mat(1, 1, CV_8U, cv::Scalar(255));  // degenerate: one texel
  frame.offset -= Eigen::Vector2d(box.x, box.y);
  return mask(box).clone();
}

// The texels of the pages a packing needs, each cropped to its highest
// footprint (as allocate_pages crops them).
double packed_texels(const std::vector<cv::Mat>& footprints,
                     const std::vector<FootprintPlacement>& placements,
                     int width,
                     int num_pages) {
  std::vector<int> height(num_pages, 0);
  for (std::size_t i = 0; i < footprints.size(); ++i) {
    const FootprintPlacement& p = placements[i];
    const int h = p.quarter_turns % 2 == 0 ? footprints[i].rows : footprints[i].cols;
    height[p.page] = std::max(height[p.page], p.y + h);
  }
  double texels = 0.0;
  for (int h : height) {
    const int rounded = (h + 3) / 4 * 4;  // a page's height, a multiple of 4
    texels += static_cast<double>(width) * rounded;
  }
  return texels;
}

// Packs the charts at the texel scale, shrinking it until the pages
// suffice; sets every frame's map into its page.
Packing pack_charts(const std::vector<Chart>& charts,
                    std::vector<ChartFrame>& frames,
                    const FlatPatches& flat,
                    const TextureOptions& options) {
  const int num_charts = static_cast<int>(frames.size());
  const int page_size = options.atlas_size;
  Packing packing;
  packing.scale = options.texel_scale;
  const bool has_flat = !flat.colours.empty();
  std::vector<cv::Mat> footprints(num_charts + (has_flat ? 1 : 0));
  for (int attempt = 0;; ++attempt) {
#pragma omp parallel for schedule(dynamic)
    for (int c = 0; c < num_charts; ++c) {
      footprints[c] = chart_footprint(charts[c], frames[c], packing.scale, page_size);
    }
    if (has_flat) {
      footprints[num_charts] = cv::Mat(flat.rows * kFlatCell, flat.columns * kFlatCell, CV_8U, cv::Scalar(255));
    }
    // Page width: a few widths around the square root of the footprints'
    // area (small models get a page about their size, not a long strip),
    // keeping the packing with the fewest texels; a full page if the charts
    // need more than one.
    double area = 0.0;
    int widest = 1;
    for (const cv::Mat& f : footprints) {
      area += cv::countNonZero(f);
      widest = std::max(widest, std::min(f.cols, f.rows));
    }
    std::vector<int> widths;
    for (const double factor : {1.05, 1.15, 1.3, 1.5}) {
      widths.push_back(
          std::min(page_size, std::max(widest, (static_cast<int>(factor * std::sqrt(area)) + 15) / 16 * 16)));
      if (widths.back() == page_size) break;
    }
    // The widths are packed in parallel, and the first with the fewest
    // texels is kept.
    std::vector<std::vector<FootprintPlacement>> placements(widths.size());
    std::vector<int> pages(widths.size(), 0);
    std::vector<double> texels(widths.size(), 0.0);
    std::vector<std::exception_ptr> failures(widths.size());
#pragma omp parallel for schedule(dynamic)
    for (int w = 0; w < static_cast<int>(widths.size()); ++w) {
      try {
        placements[w] = pack_footprints(footprints, options.padding, widths[w], page_size, &pages[w]);
        texels[w] = packed_texels(footprints, placements[w], widths[w], pages[w]);
      } catch (...) {
        failures[w] = std::current_exception();  // an exception may not leave the parallel loop
      }
    }
    for (const std::exception_ptr& failure : failures) {
      if (failure) std::rethrow_exception(failure);
    }
    const auto best = std::min_element(texels.begin(), texels.end()) - texels.begin();
    packing.page_width = widths[best];
    packing.num_pages = pages[best];
    packing.placements = std::move(placements[best]);
    if (packing.num_pages <= options.max_atlases || attempt > 30) break;
    packing.scale *= 0.8;
  }
  packing.footprint_sizes.resize(footprints.size());
  for (std::size_t i = 0; i < footprints.size(); ++i) packing.footprint_sizes[i] = footprints[i].size();
  for (int c = 0; c < num_charts; ++c) {
    const FootprintPlacement& p = packing.placements[c];
    const QuarterTurn turn = quarter_turn(footprints[c].cols, footprints[c].rows, p.quarter_turns);
    frames[c].offset = turn.linear * frames[c].offset + turn.offset + Eigen::Vector2d(p.x, p.y);
    frames[c].linear = turn.linear * frames[c].linear;
  }
  return packing;
}

// The placed footprint's rectangle on its page.
cv::Rect placed_rect(const Packing& packing, std::size_t i) {
  const FootprintPlacement& p = packing.placements[i];
  const cv::Size s = packing.footprint_sizes[i];
  return p.quarter_turns % 2 == 0 ? cv::Rect(p.x, p.y, s.width, s.height) : cv::Rect(p.x, p.y, s.height, s.width);
}

// Black pages cropped in height to what the packing uses, and their
// (empty) masks of filled texels.
void allocate_pages(const Packing& packing, int page_size, Atlas& atlas, std::vector<cv::Mat>& filled) {
  std::vector<int> used_height(packing.num_pages, 1);
  for (std::size_t i = 0; i < packing.placements.size(); ++i) {
    const cv::Rect r = placed_rect(packing, i);
    used_height[packing.placements[i].page] = std::max(used_height[packing.placements[i].page], r.y + r.height);
  }
  filled.resize(packing.num_pages);
  for (int p = 0; p < packing.num_pages; ++p) {
    // Heights rounded up to a multiple of 4 keep block-compressing tools happy.
    const int h = std::min(page_size, (used_height[p] + 3) / 4 * 4);
    atlas.pages.emplace_back(h, packing.page_width, CV_8UC3, cv::Scalar(0, 0, 0));
    filled[p] = cv::Mat(h, packing.page_width, CV_8U, cv::Scalar(0));
  }
}

// The chart of every face and its index among the chart's faces (-1: none).
struct FaceCharts {
  std::vector<int> chart, local;
};

FaceCharts chart_of_faces(std::size_t num_faces, const std::vector<Chart>& charts) {
  FaceCharts out{std::vector<int>(num_faces, -1), std::vector<int>(num_faces, -1)};
  for (std::size_t c = 0; c < charts.size(); ++c) {
    for (std::size_t i = 0; i < charts[c].faces.size(); ++i) {
      out.chart[charts[c].faces[i]] = static_cast<int>(c);
      out.local[charts[c].faces[i]] = static_cast<int>(i);
    }
  }
  return out;
}

// A seam edge of a face: the neighbour across it lies in another chart, and
// texels near it are blended with that chart's view.
struct SeamEdge {
  int corner;  // edge from corner to corner + 1
  int chart;
  Eigen::Vector3f offset_a, offset_b;  // the neighbour chart's offsets at the edge's ends
};

// What every chart's texels are made from.
struct AtlasSources {
  const TriangleMesh& mesh;
  const MeshTopology& topology;
  const FaceViewCandidates& candidates;
  const std::vector<Chart>& charts;
  const std::vector<TextureView>& views;
  const std::vector<Eigen::Vector3f>& gains;
  const SeamLeveling& leveling;
  const FaceCharts& face_charts;
};

// The seam edges of local face local_face of chart c (at most 3).
int find_seam_edges(const AtlasSources& src, int c, std::size_t local_face, std::array<SeamEdge, 3>& seams) {
  const std::vector<Chart>& charts = src.charts;
  const Eigen::Vector3i& face = charts[c].local_faces[local_face];
  const int mesh_face = charts[c].faces[local_face];
  int num_seams = 0;
  for (int k = 0; k < 3; ++k) {
    const int g = src.topology.face_neighbors[mesh_face][k];
    if (g < 0 || src.face_charts.chart[g] < 0 || src.face_charts.chart[g] == c) continue;
    const int other = src.face_charts.chart[g];
    // Only a view that passed visibility and the photo-consistency check
    // for this face may colour it (else an occluder seen by the
    // neighbour's view could bleed in).
    bool allowed = false;
    for (int i = src.candidates.begin(mesh_face); i < src.candidates.end(mesh_face); ++i) {
      allowed = allowed || src.candidates.samples[i].view == charts[other].view;
    }
    if (!allowed) continue;
    const Eigen::Vector3i& other_face = charts[other].local_faces[src.face_charts.local[g]];
    SeamEdge seam{k, other, Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()};
    for (int cc = 0; cc < 3; ++cc) {
      const int v = charts[other].vertices[other_face[cc]];
      if (v == charts[c].vertices[face[k]]) seam.offset_a = src.leveling.offsets[other][other_face[cc]];
      if (v == charts[c].vertices[face[(k + 1) % 3]]) {
        seam.offset_b = src.leveling.offsets[other][other_face[cc]];
      }
    }
    seams[num_seams++] = seam;
  }
  return num_seams;
}

// Local blending: the texel's colour rgb mixed with the nearest seam's view
// at the same surface point, half-and-half on the seam, own view only
// blend_width texels away from it.
Eigen::Vector3f blend_across_seams(const AtlasSources& src,
                                   int c,
                                   const Eigen::Vector3i& face,
                                   const std::vector<Eigen::Vector2d>& texel,
                                   const Eigen::Vector2d& centre,
                                   const Eigen::Vector3d& w,
                                   const std::array<SeamEdge, 3>& seams,
                                   int num_seams,
                                   double blend_width,
                                   const Eigen::Vector3f& rgb) {
  double best = blend_width;
  const SeamEdge* nearest = nullptr;
  double along = 0.0;
  for (int k = 0; k < num_seams; ++k) {
    const Eigen::Vector2d& a = texel[face[seams[k].corner]];
    const Eigen::Vector2d& b = texel[face[(seams[k].corner + 1) % 3]];
    const double t = std::clamp((centre - a).dot(b - a) / std::max(1e-12, (b - a).squaredNorm()), 0.0, 1.0);
    const double d = (centre - (a + t * (b - a))).norm();
    if (d < best) {
      best = d;
      nearest = &seams[k];
      along = t;
    }
  }
  if (!nearest) return rgb;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  for (int cc = 0; cc < 3; ++cc) {
    point += w[cc] * src.mesh.vertices[src.charts[c].vertices[face[cc]]].cast<double>();
  }
  const int other_view = src.charts[nearest->chart].view;
  const Eigen::Vector3d p = src.views[other_view].project(point);
  if (p.z() <= 0.0) return rgb;
  const Eigen::Vector3f other =
      src.gains[other_view].cwiseProduct(sample_rgb(src.views[other_view].image, p.x(), p.y())) +
      static_cast<float>(1.0 - along) * nearest->offset_a + static_cast<float>(along) * nearest->offset_b;
  const float t = static_cast<float>(0.5 * (1.0 - best / blend_width));
  return (1.0f - t) * rgb + t * other;
}

// Fills chart c's rectangle r of image (and mask) from its view: the photo
// times the gain plus the leveling offset, blended across seams. Writes the
// chart's UVs.
void fill_chart(const AtlasSources& src,
                int c,
                const ChartFrame& frame,
                double blend_width,
                cv::Mat& image,
                cv::Mat& mask,
                std::vector<Eigen::Vector2f>& uvs) {
  const Chart& chart = src.charts[c];
  const TextureView& view = src.views[chart.view];
  const Eigen::Vector3f gain = src.gains[chart.view];
  const Eigen::Matrix2d to_photo = frame.linear.inverse();
  std::vector<Eigen::Vector2d> texel(frame.pixels.size());
  uvs.resize(frame.pixels.size());
  for (std::size_t i = 0; i < frame.pixels.size(); ++i) {
    texel[i] = frame.linear * frame.pixels[i] + frame.offset;
    uvs[i] =
        Eigen::Vector2f(static_cast<float>(texel[i].x() / image.cols), static_cast<float>(texel[i].y() / image.rows));
  }
  const auto& offsets = src.leveling.offsets[c];
  for (std::size_t local_face = 0; local_face < chart.local_faces.size(); ++local_face) {
    const Eigen::Vector3i& face = chart.local_faces[local_face];
    std::array<SeamEdge, 3> seams;
    const int num_seams = blend_width > 0.0 ? find_seam_edges(src, c, local_face, seams) : 0;
    raster_triangle(texel[face[0]], texel[face[1]], texel[face[2]], image.cols, image.rows,
                    [&](int x, int y, const Eigen::Vector3d& w) {
                      const Eigen::Vector2d centre(x + 0.5, y + 0.5);
                      // Texel centre back to photo pixels (the map is affine).
                      const Eigen::Vector2d q = to_photo * (centre - frame.offset);
                      const Eigen::Vector3f offset = static_cast<float>(w[0]) * offsets[face[0]] +
                                                     static_cast<float>(w[1]) * offsets[face[1]] +
                                                     static_cast<float>(w[2]) * offsets[face[2]];
                      const Eigen::Vector3f rgb = gain.cwiseProduct(sample_rgb(view.image, q.x(), q.y())) + offset;
                      image.at<cv::Vec3b>(y, x) = to_bgr(
                          blend_across_seams(src, c, face, texel, centre, w, seams, num_seams, blend_width, rgb));
                      mask.at<std::uint8_t>(y, x) = 255;
                    });
  }
}

// The flat-coloured patches of faces that no view sees: the block's
// patches in rows of its placed (maybe turned) rectangle.
void place_flat_faces(
    const FlatPatches& flat, const Packing& packing, int num_charts, Atlas& atlas, std::vector<cv::Mat>& filled) {
  const int num_flat = static_cast<int>(flat.patch_of.size());
  atlas.flat_page.resize(num_flat);
  atlas.flat_uvs.resize(num_flat);
  if (flat.colours.empty()) return;
  const cv::Rect block = placed_rect(packing, static_cast<std::size_t>(num_charts));
  const int page = packing.placements[static_cast<std::size_t>(num_charts)].page;
  cv::Mat& image = atlas.pages[page];
  const int per_row = block.width / kFlatCell;
  std::vector<Eigen::Vector2f> uv_of(flat.colours.size());
  for (std::size_t k = 0; k < flat.colours.size(); ++k) {
    const cv::Rect r(block.x + static_cast<int>(k % per_row) * kFlatCell,
                     block.y + static_cast<int>(k / per_row) * kFlatCell, kFlatCell, kFlatCell);
    image(r).setTo(flat.colours[k]);
    filled[page](r).setTo(255);
    uv_of[k] = Eigen::Vector2f(static_cast<float>((r.x + 0.5 * r.width) / image.cols),
                               static_cast<float>((r.y + 0.5 * r.height) / image.rows));
  }
  for (int k = 0; k < num_flat; ++k) {
    atlas.flat_page[k] = page;
    atlas.flat_uvs[k] = uv_of[flat.patch_of[k]];
  }
}

}  // namespace

Atlas build_atlas(const TriangleMesh& mesh,
                  const MeshTopology& topology,
                  const FaceViewCandidates& candidates,
                  const std::vector<Chart>& charts,
                  const std::vector<TextureView>& views,
                  const std::vector<Eigen::Vector3f>& gains,
                  const SeamLeveling& leveling,
                  const std::vector<FlatFace>& flat_faces,
                  const TextureOptions& options,
                  Reporter& reporter) {
  const int num_charts = static_cast<int>(charts.size());
  std::vector<ChartFrame> frames = project_charts(mesh, charts, views);
  const FlatPatches flat = flat_patches(flat_faces);
  const Packing packing = pack_charts(charts, frames, flat, options);

  Atlas atlas;
  atlas.texel_scale = packing.scale;
  std::vector<cv::Mat> filled;
  allocate_pages(packing, options.atlas_size, atlas, filled);

  atlas.chart_page.resize(num_charts);
  atlas.chart_uvs.resize(num_charts);
  const FaceCharts face_charts = chart_of_faces(mesh.faces.size(), charts);
  const AtlasSources sources{mesh, topology, candidates, charts, views, gains, leveling, face_charts};
  const double blend_width = options.local_blending ? options.seam_blend_texels : 0.0;
  reporter.begin("atlas", num_charts);
#pragma omp parallel for schedule(dynamic)
  for (int c = 0; c < num_charts; ++c) {
    const int page = packing.placements[c].page;
    atlas.chart_page[c] = page;
    fill_chart(sources, c, frames[c], blend_width, atlas.pages[page], filled[page], atlas.chart_uvs[c]);
    reporter.advance();
  }
  reporter.end();

  place_flat_faces(flat, packing, num_charts, atlas, filled);
  for (int p = 0; p < packing.num_pages; ++p) dilate(atlas.pages[p], filled[p], options.padding + 1);
  return atlas;
}

double atlas_coverage(const TexturedMesh& mesh) {
  double covered = 0.0, total = 0.0;
  for (std::size_t page = 0; page < mesh.atlases.size() && page < mesh.indices.size(); ++page) {
    const cv::Mat& image = mesh.atlases[page];
    cv::Mat mask(image.rows, image.cols, CV_8U, cv::Scalar(0));
    const std::vector<std::uint32_t>& indices = mesh.indices[page];
    auto texel = [&](std::uint32_t i) {
      return Eigen::Vector2d(mesh.uvs[i].x() * double(image.cols), mesh.uvs[i].y() * double(image.rows));
    };
    for (std::size_t k = 0; k + 2 < indices.size(); k += 3) {
      raster_triangle(texel(indices[k]), texel(indices[k + 1]), texel(indices[k + 2]), image.cols, image.rows,
                      [&](int x, int y, const Eigen::Vector3d&) { mask.at<std::uint8_t>(y, x) = 255; });
    }
    covered += cv::countNonZero(mask);
    total += static_cast<double>(image.total());
  }
  return total > 0.0 ? covered / total : 0.0;
}

}  // namespace hos::texture
