#include "texture/atlas_packing.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace hos::texture {

cv::Mat turn_mask(const cv::Mat& mask, int quarter_turns) {
  cv::Mat out;
  switch (((quarter_turns % 4) + 4) % 4) {
    case 1:
      cv::rotate(mask, out, cv::ROTATE_90_CLOCKWISE);
      return out;
    case 2:
      cv::rotate(mask, out, cv::ROTATE_180);
      return out;
    case 3:
      cv::rotate(mask, out, cv::ROTATE_90_COUNTERCLOCKWISE);
      return out;
    default:
      return mask;
  }
}

QuarterTurn quarter_turn(int width, int height, int quarter_turns) {
  QuarterTurn t;
  const double w = width, h = height;
  switch (((quarter_turns % 4) + 4) % 4) {
    case 1:  // (u, v) -> (h - v, u)
      t.linear << 0, -1, 1, 0;
      t.offset = Eigen::Vector2d(h, 0);
      break;
    case 2:  // (u, v) -> (w - u, h - v)
      t.linear << -1, 0, 0, -1;
      t.offset = Eigen::Vector2d(w, h);
      break;
    case 3:  // (u, v) -> (v, w - u)
      t.linear << 0, 1, -1, 0;
      t.offset = Eigen::Vector2d(0, w);
      break;
    default:
      break;
  }
  return t;
}

namespace {

// A turned mask as the packer tests it: its runs of occupied texels, row by
// row (a concave shape's hollows stay open to other footprints).
struct Run {
  int row, begin, end;
};

std::vector<Run> runs_of(const cv::Mat& mask) {
  std::vector<Run> runs;
  for (int y = 0; y < mask.rows; ++y) {
    const std::uint8_t* row = mask.ptr<std::uint8_t>(y);
    for (int x = 0; x < mask.cols; ++x) {
      if (!row[x]) continue;
      const int begin = x;
      while (x < mask.cols && row[x]) ++x;
      runs.push_back(Run{y, begin, x});
    }
  }
  return runs;
}

// One orientation of a footprint: its occupied texels and the span test of
// those texels dilated by the gap (origin gap texels up and left of the mask's).
struct Turn {
  cv::Mat mask;
  std::vector<Run> test;
};

// The texels of a page taken by placed masks, as the run of free texels from
// each texel rightwards (positive) or of taken ones (negative), and the
// longest free run per row: a position is tested in one lookup per row, and
// a failed row says how far right the next candidate lies.
class PageGrid {
 public:
  PageGrid(int width, int height)
      : width_(width), height_(height), run_(std::size_t(width) * height, 1), longest_(height) {
    for (int y = 0; y < height; ++y) update_row(y);
  }

  // The first position (lowest row, then leftmost column) of the turn's
  // top-left texel where its mask lies inside the page, its bottom edge at
  // most max_bottom, and its dilated runs (clipped to the page) meet no
  // taken texel.
  bool first_fit(const Turn& t, int gap, int first_row, int max_bottom, int* out_x, int* out_y) const {
    const std::vector<Run>& s = t.test;
    // The run that blocked last is tested first: the runs that blocked one
    // candidate mostly block its neighbours too. (Any blocking run's skip
    // is safe, so the order changes the work, not the place found.)
    std::size_t blocker = 0;
    for (int y = first_row; y + t.mask.rows <= std::min(height_, max_bottom); ++y) {
      if (!rows_may_fit(s, gap, y, blocker)) continue;
      for (int x = 0; x + t.mask.cols <= width_;) {
        const int next = blocked_until(s, gap, x, y, blocker);
        if (next < 0) {
          *out_x = x;
          *out_y = y;
          return true;
        }
        x = std::max(x + 1, next);
      }
    }
    return false;
  }

  void occupy(const cv::Mat& mask, int x0, int y0) {
    for (int y = 0; y < mask.rows; ++y) {
      const std::uint8_t* row = mask.ptr<std::uint8_t>(y);
      bool any = false;
      for (int x = 0; x < mask.cols; ++x) {
        if (!row[x]) continue;
        run_[std::size_t(y0 + y) * width_ + x0 + x] = -1;
        any = true;
      }
      if (any) update_row(y0 + y);
    }
  }

 private:
  void update_row(int y) {
    std::int16_t* r = &run_[std::size_t(y) * width_];
    int free = 0, taken = 0, longest = 0;
    for (int x = width_ - 1; x >= 0; --x) {
      if (r[x] < 0) {
        free = 0;
        r[x] = static_cast<std::int16_t>(-++taken);
      } else {
        taken = 0;
        r[x] = static_cast<std::int16_t>(++free);
        longest = std::max(longest, free);
      }
    }
    longest_[y] = longest;
  }

  // Quick rejection: some run (less what clipping may cut) is longer than
  // the longest free run of its page row. Starts at runs[blocker] and sets
  // blocker to the run that fails.
  bool rows_may_fit(const std::vector<Run>& runs, int gap, int y, std::size_t& blocker) const {
    for (std::size_t k = 0, i = blocker; k < runs.size(); ++k, i = i + 1 == runs.size() ? 0 : i + 1) {
      const Run& r = runs[i];
      const int row = y - gap + r.row;
      if (row >= 0 && row < height_ && longest_[row] < r.end - r.begin - 2 * gap) {
        blocker = i;
        return false;
      }
    }
    return true;
  }

  // -1 if the runs fit at (x, y); else the next column worth trying. Starts
  // at runs[blocker] and sets blocker to the run that blocks.
  int blocked_until(const std::vector<Run>& runs, int gap, int x, int y, std::size_t& blocker) const {
    for (std::size_t k = 0, i = blocker; k < runs.size(); ++k, i = i + 1 == runs.size() ? 0 : i + 1) {
      const Run& r = runs[i];
      const int row = y - gap + r.row;
      if (row < 0 || row >= height_) continue;
      const int b = std::max(0, x - gap + r.begin), e = std::min(width_, x - gap + r.end);
      if (b >= e) continue;
      const std::int16_t* texels = &run_[std::size_t(row) * width_];
      const int free = texels[b];
      if (free >= e - b) continue;
      // The run must start past the taken run at b (free < 0) or at b + free.
      const int taken_at = free < 0 ? b : b + free;
      blocker = i;
      return taken_at - texels[taken_at] + gap - r.begin;
    }
    return -1;
  }

  int width_, height_;
  std::vector<std::int16_t> run_;
  std::vector<int> longest_;
};

}  // namespace

std::vector<FootprintPlacement> pack_footprints(
    const std::vector<cv::Mat>& masks, int gap, int page_width, int page_height, int* num_pages) {
  if (page_width > std::numeric_limits<std::int16_t>::max()) throw std::invalid_argument("atlas page too wide");
  std::vector<int> order(masks.size());
  std::iota(order.begin(), order.end(), 0);
  // Largest first (occupied texels): the small ones then fill the hollows.
  std::vector<int> area(masks.size());
  for (std::size_t i = 0; i < masks.size(); ++i) area[i] = cv::countNonZero(masks[i]);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return area[a] > area[b]; });
  const cv::Mat ring = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * gap + 1, 2 * gap + 1));
  std::vector<FootprintPlacement> placements(masks.size());
  std::vector<PageGrid> pages;
  // Per page: where footprints of these sides found their place (row), or
  // page_height if none.
  struct Found {
    int short_side, long_side, row;
  };
  std::vector<std::vector<Found>> found;
  for (int i : order) {
    cv::Mat dilated;
    cv::copyMakeBorder(masks[i], dilated, gap, gap, gap, gap, cv::BORDER_CONSTANT, cv::Scalar(0));
    if (gap > 0) cv::dilate(dilated, dilated, ring);
    const bool square = masks[i].rows == masks[i].cols;
    std::vector<Turn> turns;
    for (int q = 0; q < 4; ++q) {
      if (q > 0 && square && masks[i].total() <= 64) break;  // tiny: turning gains nothing
      turns.push_back(Turn{turn_mask(masks[i], q), runs_of(turn_mask(dilated, q))});
    }
    // The first page that takes it; there the turn whose bottom edge is
    // lowest (keeps the filled part compact), then the leftmost. The search
    // starts at the row where an earlier footprint no larger either way
    // found its place (or none): the rows above had no room for that one
    // and have less now, so dense pages are not scanned again and again.
    const int short_side = std::min(dilated.rows, dilated.cols), long_side = std::max(dilated.rows, dilated.cols);
    FootprintPlacement chosen;
    auto try_page = [&](int page) {
      int first_row = 0;
      for (const Found& f : found[page]) {
        if (f.short_side <= short_side && f.long_side <= long_side) first_row = std::max(first_row, f.row);
      }
      long long best = std::numeric_limits<long long>::max();
      int best_bottom = page_height;  // a turn reaching lower cannot win
      for (int q = 0; q < static_cast<int>(turns.size()) && first_row < page_height; ++q) {
        int x = 0, y = 0;
        if (!pages[page].first_fit(turns[q], gap, first_row, best_bottom, &x, &y)) continue;
        const long long key = static_cast<long long>(y + turns[q].mask.rows) * page_width + x;
        if (key < best) {
          best = key;
          best_bottom = y + turns[q].mask.rows;
          chosen = FootprintPlacement{page, x, y, q};
        }
      }
      found[page].push_back(Found{short_side, long_side, chosen.page >= 0 ? chosen.y : page_height});
      return chosen.page >= 0;
    };
    bool placed = false;
    for (int page = 0; page < static_cast<int>(pages.size()) && !placed; ++page) placed = try_page(page);
    if (!placed) {
      pages.emplace_back(page_width, page_height);
      found.emplace_back();
      if (!try_page(static_cast<int>(pages.size()) - 1)) {
        throw std::invalid_argument("a chart is larger than the atlas page");
      }
    }
    pages[chosen.page].occupy(turns[chosen.quarter_turns].mask, chosen.x, chosen.y);
    placements[i] = chosen;
  }
  *num_pages = static_cast<int>(pages.size());
  return placements;
}

}  // namespace hos::texture
