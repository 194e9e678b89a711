#include "texture/atlas.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <random>

#include "core/reporter.h"
#include "synth/shapes.h"
#include "tests/texture/scene_fixtures.h"
#include "texture/atlas_packing.h"
#include "texture/charts.h"
#include "texture/texture_mesh.h"

namespace hos::texture {
namespace {

using testing::strip_topology;

// Random convex and concave blobs: ellipses, triangles and L shapes.
std::vector<cv::Mat> random_masks(int count, int max_size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> size(3, max_size);
  std::uniform_int_distribution<int> kind(0, 2);
  std::vector<cv::Mat> masks;
  for (int i = 0; i < count; ++i) {
    const int w = size(rng), h = size(rng);
    cv::Mat m(h, w, CV_8U, cv::Scalar(0));
    switch (kind(rng)) {
      case 0:
        cv::ellipse(m, cv::Point(w / 2, h / 2), cv::Size(w / 2, h / 2), 0, 0, 360, cv::Scalar(255), cv::FILLED);
        break;
      case 1: {
        const std::vector<cv::Point> tri = {{0, 0}, {w - 1, 0}, {0, h - 1}};
        cv::fillConvexPoly(m, tri, cv::Scalar(255));
        break;
      }
      default:
        m(cv::Rect(0, 0, std::max(1, w / 3), h)).setTo(255);
        m(cv::Rect(0, h - std::max(1, h / 3), w, std::max(1, h / 3))).setTo(255);
    }
    masks.push_back(m);
  }
  return masks;
}

// Draws every placed mask into its page; fails on a texel claimed twice.
std::vector<cv::Mat> draw_placements(const std::vector<cv::Mat>& masks,
                                     const std::vector<FootprintPlacement>& placements,
                                     int width,
                                     int height,
                                     int pages) {
  std::vector<cv::Mat> canvas(pages);
  for (auto& c : canvas) c = cv::Mat(height, width, CV_8U, cv::Scalar(0));
  for (std::size_t i = 0; i < masks.size(); ++i) {
    const FootprintPlacement& p = placements[i];
    EXPECT_GE(p.page, 0);
    EXPECT_LT(p.page, pages);
    const cv::Mat turned = turn_mask(masks[i], p.quarter_turns);
    EXPECT_GE(p.x, 0);
    EXPECT_GE(p.y, 0);
    EXPECT_LE(p.x + turned.cols, width);
    EXPECT_LE(p.y + turned.rows, height);
    if (p.page < 0 || p.page >= pages || p.x + turned.cols > width || p.y + turned.rows > height) continue;
    for (int y = 0; y < turned.rows; ++y) {
      for (int x = 0; x < turned.cols; ++x) {
        if (!turned.at<std::uint8_t>(y, x)) continue;
        std::uint8_t& texel = canvas[p.page].at<std::uint8_t>(p.y + y, p.x + x);
        EXPECT_EQ(texel, 0) << "mask " << i << " overlaps at " << p.x + x << "," << p.y + y;
        texel = 255;
      }
    }
  }
  return canvas;
}

TEST(AtlasPacking, FootprintsNeverOverlapAndStayInPages) {
  const std::vector<cv::Mat> masks = random_masks(600, 90, 3);
  int pages = 0;
  const std::vector<FootprintPlacement> placements = pack_footprints(masks, 0, 512, 512, &pages);
  EXPECT_GE(pages, 2);
  draw_placements(masks, placements, 512, 512, pages);
}

// The packer follows the shapes: occupied texels over the texels of the
// pages up to the highest occupied row. Rectangles around these shapes
// (ellipses pi/4, triangles 1/2, L shapes about 5/9 of their box) would
// reach at most 0.6 even if the rectangles themselves were packed perfectly.
// Two footprints' texels keep gap free texels between them in x and y:
// every placed mask, dilated by the gap, meets no other mask's texel.
TEST(AtlasPacking, FootprintsKeepTheGapBetweenThem) {
  const std::vector<cv::Mat> masks = random_masks(300, 40, 7);
  const int gap = 2;
  int pages = 0;
  const std::vector<FootprintPlacement> placements = pack_footprints(masks, gap, 256, 256, &pages);
  std::vector<cv::Mat> owner(pages);
  for (auto& o : owner) o = cv::Mat(256, 256, CV_32S, cv::Scalar(-1));
  for (std::size_t i = 0; i < masks.size(); ++i) {
    const FootprintPlacement& p = placements[i];
    const cv::Mat turned = turn_mask(masks[i], p.quarter_turns);
    cv::Mat region = owner[p.page](cv::Rect(p.x, p.y, turned.cols, turned.rows));
    region.setTo(static_cast<int>(i), turned);
  }
  const cv::Mat ring = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * gap + 1, 2 * gap + 1));
  int violations = 0;
  for (std::size_t i = 0; i < masks.size(); ++i) {
    const FootprintPlacement& p = placements[i];
    cv::Mat page_mask(256, 256, CV_8U, cv::Scalar(0));
    turn_mask(masks[i], p.quarter_turns)
        .copyTo(page_mask(
            cv::Rect(p.x, p.y, turn_mask(masks[i], p.quarter_turns).cols, turn_mask(masks[i], p.quarter_turns).rows)));
    cv::dilate(page_mask, page_mask, ring);
    for (int y = 0; y < 256; ++y) {
      for (int x = 0; x < 256; ++x) {
        const int o = owner[p.page].at<int>(y, x);
        if (page_mask.at<std::uint8_t>(y, x) && o >= 0 && o != static_cast<int>(i)) ++violations;
      }
    }
  }
  EXPECT_EQ(violations, 0);
  draw_placements(masks, placements, 256, 256, pages);
}

TEST(AtlasPacking, IrregularShapesFillMostOfThePage) {
  const std::vector<cv::Mat> masks = random_masks(400, 60, 5);
  int pages = 0;
  const std::vector<FootprintPlacement> placements = pack_footprints(masks, 0, 512, 4096, &pages);
  ASSERT_EQ(pages, 1);
  const cv::Mat canvas = draw_placements(masks, placements, 512, 4096, pages)[0];
  int used_rows = 0;
  for (int y = 0; y < canvas.rows; ++y) {
    if (cv::countNonZero(canvas.row(y)) > 0) used_rows = y + 1;
  }
  const double fill = cv::countNonZero(canvas) / (512.0 * used_rows);
  std::cout << "[ figures  ] packed " << masks.size() << " shapes: " << fill << " of the used page\n";
  EXPECT_GT(fill, 0.7);
}

TEST(AtlasPacking, TurnsLongFootprintsToFitThePage) {
  std::vector<cv::Mat> masks = {cv::Mat(10, 200, CV_8U, cv::Scalar(255)), cv::Mat(200, 10, CV_8U, cv::Scalar(255))};
  int pages = 0;
  const std::vector<FootprintPlacement> placements = pack_footprints(masks, 0, 64, 256, &pages);
  EXPECT_EQ(pages, 1);
  EXPECT_EQ(placements[0].quarter_turns % 2, 1);  // 200 wide does not fit 64 unless turned
  draw_placements(masks, placements, 64, 256, pages);
}

TEST(AtlasPacking, OversizedFootprintThrows) {
  const std::vector<cv::Mat> masks = {cv::Mat(600, 600, CV_8U, cv::Scalar(255))};
  int pages = 0;
  EXPECT_THROW(pack_footprints(masks, 0, 512, 512, &pages), std::invalid_argument);
}

TEST(AtlasPacking, QuarterTurnMapsTexelCentresLikeTurnMask) {
  cv::Mat mask(5, 8, CV_8U, cv::Scalar(0));
  mask.at<std::uint8_t>(1, 6) = 255;  // row 1, column 6
  for (int q = 0; q < 4; ++q) {
    const cv::Mat turned = turn_mask(mask, q);
    const QuarterTurn t = quarter_turn(mask.cols, mask.rows, q);
    const Eigen::Vector2d centre = t.linear * Eigen::Vector2d(6.5, 1.5) + t.offset;
    ASSERT_EQ(turned.at<std::uint8_t>(static_cast<int>(centre.y()), static_cast<int>(centre.x())), 255) << q;
    EXPECT_NEAR(centre.x() - std::floor(centre.x()), 0.5, 1e-12);
  }
}

// A 10x10 page: the triangle (0,0) (10,0) (0,10) holds the centres of the
// texels with x + y <= 9, 55 of 100; a degenerate triangle holds none.
TEST(AtlasCoverage, CountsTexelCentresInsideTriangles) {
  TexturedMesh mesh;
  mesh.uvs = {{0.0f, 0.0f}, {1.0f, 0.0f}, {0.0f, 1.0f}, {0.5f, 0.5f}};
  mesh.positions.assign(4, Eigen::Vector3f::Zero());
  mesh.normals.assign(4, Eigen::Vector3f::UnitZ());
  mesh.atlases = {cv::Mat(10, 10, CV_8UC3, cv::Scalar::all(0))};
  mesh.indices = {{0, 1, 2, 3, 3, 3}};
  EXPECT_DOUBLE_EQ(atlas_coverage(mesh), 0.55);
  mesh.uvs.push_back({1.0f, 1.0f});
  mesh.indices[0].insert(mesh.indices[0].end(), {1, 4, 2});
  EXPECT_DOUBLE_EQ(atlas_coverage(mesh), 1.0);
}

// Every face seen by the listed views with the given projected area each.
FaceViewCandidates candidates_of(const std::vector<std::vector<std::pair<int, float>>>& per_face) {
  FaceViewCandidates c;
  c.offsets.push_back(0);
  for (const auto& views : per_face) {
    for (const auto& [view, area] : views) {
      FaceViewSample s;
      s.view = view;
      s.projected_area_px = area;
      c.samples.push_back(s);
    }
    c.offsets.push_back(static_cast<int>(c.samples.size()));
  }
  return c;
}

TEST(ChartMerging, SmallChartTakesItsNeighboursViewWhereItSeesIt) {
  const MeshTopology topology = strip_topology(10);
  // Faces 4-5 picked view 1, the rest view 0; both views see every face.
  std::vector<std::vector<std::pair<int, float>>> seen(10, {{0, 100.0f}, {1, 120.0f}});
  std::vector<int> labels = {0, 0, 0, 0, 1, 1, 0, 0, 0, 0};
  EXPECT_EQ(merge_small_charts(topology, candidates_of(seen), 1000.0, labels), 1);
  EXPECT_EQ(labels, std::vector<int>(10, 0));

  // Off: nothing changes.
  labels = {0, 0, 0, 0, 1, 1, 0, 0, 0, 0};
  EXPECT_EQ(merge_small_charts(topology, candidates_of(seen), 0.0, labels), 0);
  EXPECT_EQ(labels[4], 1);

  // View 0 does not see face 5: the chart cannot go whole; face 4 (seen by
  // view 0) goes over to its neighbour, face 5 keeps view 1.
  seen[5] = {{1, 120.0f}};
  labels = {0, 0, 0, 0, 1, 1, 0, 0, 0, 0};
  EXPECT_EQ(merge_small_charts(topology, candidates_of(seen), 300.0, labels), 1);
  EXPECT_EQ(labels[4], 0);
  EXPECT_EQ(labels[5], 1);

  // View 0 sees faces 4-5 at a fifth of the area: no blurrier texels.
  seen[4] = {{0, 20.0f}, {1, 120.0f}};
  seen[5] = {{0, 20.0f}, {1, 120.0f}};
  labels = {0, 0, 0, 0, 1, 1, 0, 0, 0, 0};
  EXPECT_EQ(merge_small_charts(topology, candidates_of(seen), 300.0, labels), 0);
  EXPECT_EQ(labels[4], 1);
  // Unseen faces (-1) stay unseen.
  labels = {0, 0, -1, -1, 0, 0, 0, 0, 0, 0};
  merge_small_charts(topology, candidates_of(seen), 1e6, labels);
  EXPECT_EQ(labels[2], -1);
  EXPECT_EQ(labels[3], -1);
}

// The sphere of 5120 faces from 10 photos on two rings: ten large round
// charts, the hardest case for packing by shape (round charts leave their
// corners empty); they cover at least 60% of the atlas texels.
TEST(AtlasCoverage, SphereAtlasIsMostlyTriangles) {
  const TriangleMesh mesh = synth::icosphere(4, 1.0);
  std::vector<TextureView> views;
  for (int i = 0; i < 10; ++i) {
    views.push_back(testing::make_view(testing::view_name(i), 36.0 * i + 7.0, i % 2 == 0 ? 35.0 : -35.0, 3.5));
    testing::render_sphere(views.back(), 1.0);
  }
  const TextureResult result = texture_mesh(mesh, views, TextureOptions{}, null_reporter());
  std::cout << "[ figures  ] sphere: " << result.stats.num_charts << " charts (" << result.stats.num_merged_charts
            << " merged), coverage " << result.stats.atlas_coverage << "\n";
  EXPECT_DOUBLE_EQ(result.stats.atlas_coverage, atlas_coverage(result.mesh));
  EXPECT_GE(result.stats.atlas_coverage, 0.6);
}

}  // namespace
}  // namespace hos::texture
