#include "texture/atlas.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace hos::texture {

std::vector<int> pack_shelves(std::vector<Rect>& rects, int page_width, int page_height, int* num_pages) {
  std::vector<int> order(rects.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return rects[a].height != rects[b].height ? rects[a].height > rects[b].height : rects[a].width > rects[b].width;
  });
  std::vector<int> page(rects.size(), 0);
  int current = 0, shelf_y = 0, shelf_height = 0, cursor_x = 0;
  for (int i : order) {
    Rect& r = rects[i];
    if (r.width > page_width || r.height > page_height) {
      throw std::invalid_argument("a chart is larger than the atlas page");
    }
    if (cursor_x + r.width > page_width) {  // next shelf
      shelf_y += shelf_height;
      cursor_x = 0;
      shelf_height = 0;
    }
    if (shelf_y + r.height > page_height) {  // next page
      ++current;
      shelf_y = 0;
      cursor_x = 0;
      shelf_height = 0;
    }
    r.x = cursor_x;
    r.y = shelf_y;
    cursor_x += r.width;
    shelf_height = std::max(shelf_height, r.height);
    page[i] = current;
  }
  *num_pages = rects.empty() ? 0 : current + 1;
  return page;
}

namespace {

constexpr int kFlatCell = 4;  // texels per side of a flat face's patch

struct ChartFrame {
  Eigen::Vector2d min;                  // bounding box of the projection, photo pixels
  double scale = 1.0;                   // texels per photo pixel
  std::vector<Eigen::Vector2d> pixels;  // projected chart vertices
};

// Marks texels whose centre lies in the triangle (texel coordinates) and
// calls fill(x, y, barycentric) for each.
template <typename Fill>
void raster_triangle(
    const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c, int width, int height, Fill&& fill) {
  const double area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
  if (std::abs(area) < 1e-12) return;
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}) - 0.5)));
  const int x1 = std::min(width - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()}))));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}) - 0.5)));
  const int y1 = std::min(height - 1, static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))));
  const double eps = -1e-6;
  for (int y = y0; y <= y1; ++y) {
    const double py = y + 0.5;
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5;
      const double wa = ((b.x() - px) * (c.y() - py) - (b.y() - py) * (c.x() - px)) / area;
      const double wb = ((c.x() - px) * (a.y() - py) - (c.y() - py) * (a.x() - px)) / area;
      const double wc = 1.0 - wa - wb;
      if (wa < eps || wb < eps || wc < eps) continue;
      fill(x, y, Eigen::Vector3d(wa, wb, wc));
    }
  }
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

// Every chart's vertices projected into its view (photo pixels).
std::vector<ChartFrame> project_charts(const TriangleMesh& mesh,
                                       const std::vector<Chart>& charts,
                                       const std::vector<TextureView>& views) {
  std::vector<ChartFrame> frames(charts.size());
  for (std::size_t c = 0; c < charts.size(); ++c) {
    ChartFrame& frame = frames[c];
    const TextureView& view = views[charts[c].view];
    frame.pixels.resize(charts[c].vertices.size());
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = Eigen::Vector2d::Constant(-1e300);
    for (std::size_t i = 0; i < charts[c].vertices.size(); ++i) {
      const Eigen::Vector3d p = view.project(mesh.vertices[charts[c].vertices[i]].cast<double>());
      frame.pixels[i] = p.head<2>();
      lo = lo.cwiseMin(p.head<2>());
      hi = hi.cwiseMax(p.head<2>());
    }
    frame.min = lo;
  }
  return frames;
}

// Where every chart (first) and flat-face patch (after them) goes.
struct Packing {
  std::vector<Rect> rects;
  std::vector<int> page_of;
  int num_pages = 0;
  int page_width = 0;
  double scale = 1.0;  // texels per photo pixel
};

// Packs the charts at the texel scale, shrinking it until the pages
// suffice; sets every frame's own scale.
Packing pack_charts(std::vector<ChartFrame>& frames, int num_flat, const TextureOptions& options) {
  const int num_charts = static_cast<int>(frames.size());
  const int pad = options.padding;
  const int page_size = options.atlas_size;
  Packing packing;
  packing.scale = options.texel_scale;
  packing.page_width = page_size;
  std::vector<Rect>& rects = packing.rects;
  for (int attempt = 0;; ++attempt) {
    rects.assign(num_charts + num_flat, Rect{});
    for (int c = 0; c < num_charts; ++c) {
      Eigen::Vector2d extent = Eigen::Vector2d::Zero();
      for (const auto& p : frames[c].pixels) extent = extent.cwiseMax(p - frames[c].min);
      // A chart wider than a page is scaled down on its own.
      const double limit = page_size - 2 * pad - 2;
      double s = packing.scale;
      if (extent.maxCoeff() * s > limit) s = limit / extent.maxCoeff();
      frames[c].scale = s;
      rects[c].width = static_cast<int>(std::ceil(extent.x() * s)) + 1 + 2 * pad;
      rects[c].height = static_cast<int>(std::ceil(extent.y() * s)) + 1 + 2 * pad;
    }
    for (int k = 0; k < num_flat; ++k) rects[num_charts + k] = Rect{0, 0, kFlatCell, kFlatCell};
    // Page width: the smallest power of two that holds the charts in a
    // roughly square page, so small models do not get a long thin strip.
    double area = 0.0;
    int widest = 1;
    for (const Rect& r : rects) {
      area += static_cast<double>(r.width) * r.height;
      widest = std::max(widest, r.width);
    }
    int page_width = 64;
    while (page_width < page_size && (page_width < widest || page_width < 1.15 * std::sqrt(area))) {
      page_width *= 2;
    }
    packing.page_width = std::min(page_width, page_size);
    packing.page_of = pack_shelves(rects, packing.page_width, page_size, &packing.num_pages);
    if (packing.num_pages <= options.max_atlases || attempt > 30) break;
    packing.scale *= 0.8;
  }
  return packing;
}

// Black pages cropped in height to what the packing uses, and their
// (empty) masks of filled texels.
void allocate_pages(const Packing& packing, int page_size, Atlas& atlas, std::vector<cv::Mat>& filled) {
  std::vector<int> used_height(packing.num_pages, 1);
  for (std::size_t i = 0; i < packing.rects.size(); ++i) {
    const Rect& r = packing.rects[i];
    used_height[packing.page_of[i]] = std::max(used_height[packing.page_of[i]], r.y + r.height);
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
                const Rect& r,
                int pad,
                double blend_width,
                cv::Mat& image,
                cv::Mat& mask,
                std::vector<Eigen::Vector2f>& uvs) {
  const Chart& chart = src.charts[c];
  const TextureView& view = src.views[chart.view];
  const Eigen::Vector3f gain = src.gains[chart.view];
  const Eigen::Vector2d origin(r.x + pad + 0.5, r.y + pad + 0.5);
  std::vector<Eigen::Vector2d> texel(frame.pixels.size());
  uvs.resize(frame.pixels.size());
  for (std::size_t i = 0; i < frame.pixels.size(); ++i) {
    texel[i] = origin + (frame.pixels[i] - frame.min) * frame.scale;
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
                      const Eigen::Vector2d q = frame.min + (centre - origin) / frame.scale;
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

// The flat-coloured patches of faces that no view sees.
void place_flat_faces(const std::vector<FlatFace>& flat_faces,
                      const Packing& packing,
                      int num_charts,
                      Atlas& atlas,
                      std::vector<cv::Mat>& filled) {
  const int num_flat = static_cast<int>(flat_faces.size());
  atlas.flat_page.resize(num_flat);
  atlas.flat_uvs.resize(num_flat);
  for (int k = 0; k < num_flat; ++k) {
    const Rect& r = packing.rects[num_charts + k];
    const int page = packing.page_of[num_charts + k];
    cv::Mat& image = atlas.pages[page];
    image(cv::Rect(r.x, r.y, r.width, r.height)).setTo(to_bgr(flat_faces[k].rgb));
    filled[page](cv::Rect(r.x, r.y, r.width, r.height)).setTo(255);
    atlas.flat_page[k] = page;
    atlas.flat_uvs[k] = Eigen::Vector2f(static_cast<float>((r.x + 0.5 * r.width) / image.cols),
                                        static_cast<float>((r.y + 0.5 * r.height) / image.rows));
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
  const Packing packing = pack_charts(frames, static_cast<int>(flat_faces.size()), options);

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
    const int page = packing.page_of[c];
    atlas.chart_page[c] = page;
    fill_chart(sources, c, frames[c], packing.rects[c], options.padding, blend_width, atlas.pages[page], filled[page],
               atlas.chart_uvs[c]);
    reporter.advance();
  }
  reporter.end();

  place_flat_faces(flat_faces, packing, num_charts, atlas, filled);
  for (int p = 0; p < packing.num_pages; ++p) dilate(atlas.pages[p], filled[p], options.padding + 1);
  return atlas;
}

}  // namespace hos::texture
