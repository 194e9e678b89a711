#include "texture/atlas_packing.h"

#include <algorithm>
#include <limits>
#include <numeric>
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

// A turned mask's shape as the packer sees it: per column the first and one
// past the last occupied row (columns without texels: top = height, bottom = 0).
struct Profile {
  int width = 0, height = 0;
  std::vector<int> top, bottom;
};

Profile profile_of(const cv::Mat& mask) {
  Profile p;
  p.width = mask.cols;
  p.height = mask.rows;
  p.top.assign(mask.cols, mask.rows);
  p.bottom.assign(mask.cols, 0);
  for (int y = 0; y < mask.rows; ++y) {
    const std::uint8_t* row = mask.ptr<std::uint8_t>(y);
    for (int x = 0; x < mask.cols; ++x) {
      if (!row[x]) continue;
      p.top[x] = std::min(p.top[x], y);
      p.bottom[x] = y + 1;
    }
  }
  return p;
}

struct Candidate {
  bool found = false;
  int x = 0, y = 0;
  double score = std::numeric_limits<double>::max();
};

// The best position of a profile on a page's skyline (first free row per
// column): lowest resulting top edge, then least area left below the chart.
Candidate best_position(const std::vector<int>& skyline, int page_height, const Profile& p) {
  Candidate best;
  const int page_width = static_cast<int>(skyline.size());
  for (int x = 0; x + p.width <= page_width; ++x) {
    int y = 0;
    bool fits = true;
    for (int i = 0; i < p.width; ++i) {
      if (p.top[i] >= p.height) continue;
      y = std::max(y, skyline[x + i] - p.top[i]);
      if (y + p.height > page_height) {
        fits = false;
        break;
      }
    }
    if (!fits) continue;
    long long waste = 0;
    int reach = 0;
    for (int i = 0; i < p.width; ++i) {
      if (p.top[i] >= p.height) continue;
      waste += y + p.top[i] - skyline[x + i];
      reach = std::max(reach, y + p.bottom[i]);
    }
    // Rows first keeps the skyline flat (the last page is cropped to it);
    // the waste term lets a chart drop into a matching hollow.
    const double score = static_cast<double>(reach) * p.width + static_cast<double>(waste);
    if (score < best.score) best = Candidate{true, x, y, score};
  }
  return best;
}

}  // namespace

std::vector<FootprintPlacement> pack_footprints(const std::vector<cv::Mat>& masks,
                                                int page_width,
                                                int page_height,
                                                int* num_pages) {
  std::vector<int> order(masks.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    const int sa = std::max(masks[a].rows, masks[a].cols), sb = std::max(masks[b].rows, masks[b].cols);
    return sa != sb ? sa > sb : masks[a].total() > masks[b].total();
  });
  std::vector<FootprintPlacement> placements(masks.size());
  std::vector<std::vector<int>> skylines;
  std::vector<int> lowest;  // per page: the lowest skyline row (a page is full when nothing fits above it)
  for (int i : order) {
    const bool square = masks[i].rows == masks[i].cols;
    std::vector<Profile> turns;
    for (int q = 0; q < 4; ++q) {
      if (q > 0 && square && masks[i].total() <= 64) break;  // tiny: turning gains nothing
      turns.push_back(profile_of(turn_mask(masks[i], q)));
    }
    FootprintPlacement chosen;
    double chosen_score = std::numeric_limits<double>::max();
    for (std::size_t page = 0; page < skylines.size() && chosen.page < 0; ++page) {
      for (int q = 0; q < static_cast<int>(turns.size()); ++q) {
        if (lowest[page] + std::min(turns[q].height, turns[q].width) > page_height) continue;
        const Candidate c = best_position(skylines[page], page_height, turns[q]);
        if (c.found && c.score < chosen_score) {
          chosen_score = c.score;
          chosen = FootprintPlacement{static_cast<int>(page), c.x, c.y, q};
        }
      }
    }
    if (chosen.page < 0) {  // a new page
      skylines.emplace_back(page_width, 0);
      lowest.push_back(0);
      const int page = static_cast<int>(skylines.size()) - 1;
      for (int q = 0; q < static_cast<int>(turns.size()); ++q) {
        const Candidate c = best_position(skylines[page], page_height, turns[q]);
        if (c.found && c.score < chosen_score) {
          chosen_score = c.score;
          chosen = FootprintPlacement{page, c.x, c.y, q};
        }
      }
      if (chosen.page < 0) throw std::invalid_argument("a chart is larger than the atlas page");
    }
    const Profile& p = turns[chosen.quarter_turns];
    std::vector<int>& skyline = skylines[chosen.page];
    for (int k = 0; k < p.width; ++k) {
      if (p.top[k] < p.height) skyline[chosen.x + k] = std::max(skyline[chosen.x + k], chosen.y + p.bottom[k]);
    }
    lowest[chosen.page] = *std::min_element(skyline.begin(), skyline.end());
    placements[i] = chosen;
  }
  *num_pages = static_cast<int>(skylines.size());
  return placements;
}

}  // namespace hos::texture
