// Packing of chart footprints into atlas pages by shape: every footprint,
// largest (occupied texels) first, goes where its texels, dilated by the
// gap, meet no texel already placed, in the quarter turn and position whose
// bottom edge is lowest (then leftmost) on the first page that takes it; so
// charts fill the hollows left between and inside earlier ones instead of
// taking their whole bounding rectangle, and two charts share the gap
// between them instead of each bringing its own.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

namespace hos::texture {

// Where a footprint goes: its page, the top-left corner of its turned mask
// on the page, and the number of clockwise quarter turns applied to it.
struct FootprintPlacement {
  int page = -1;
  int x = 0, y = 0;
  int quarter_turns = 0;
};

// Packs the masks (CV_8U, nonzero = occupied) into pages of page_width x
// page_height; returns one placement per mask and sets the number of pages.
// Occupied texels of different masks are more than gap texels apart in x or
// y (gap free texels between them); the page border needs no gap. Throws
// std::invalid_argument if a mask fits a page in no orientation.
std::vector<FootprintPlacement> pack_footprints(
    const std::vector<cv::Mat>& masks, int gap, int page_width, int page_height, int* num_pages);

// The mask turned clockwise by quarter_turns (0-3) quarter turns.
cv::Mat turn_mask(const cv::Mat& mask, int quarter_turns);

// Maps a point of a width x height mask (continuous texel coordinates: texel
// (x, y) spans [x, x+1] x [y, y+1]) to the mask turned clockwise by
// quarter_turns; texel centres go to texel centres.
struct QuarterTurn {
  Eigen::Matrix2d linear = Eigen::Matrix2d::Identity();
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();
};
QuarterTurn quarter_turn(int width, int height, int quarter_turns);

}  // namespace hos::texture
