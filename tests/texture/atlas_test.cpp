#include "texture/atlas.h"

#include <gtest/gtest.h>

#include <random>

namespace hos::texture {
namespace {

TEST(Atlas, ShelfPackingHasNoOverlapsAndStaysInPages) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> size(1, 120);
  std::vector<Rect> rects(500);
  for (auto& r : rects) {
    r.width = size(rng);
    r.height = size(rng);
  }
  int pages = 0;
  const std::vector<int> page = pack_shelves(rects, 512, 512, &pages);
  EXPECT_GE(pages, 1);
  for (std::size_t i = 0; i < rects.size(); ++i) {
    EXPECT_GE(rects[i].x, 0);
    EXPECT_GE(rects[i].y, 0);
    EXPECT_LE(rects[i].x + rects[i].width, 512);
    EXPECT_LE(rects[i].y + rects[i].height, 512);
    for (std::size_t j = i + 1; j < rects.size(); ++j) {
      if (page[i] != page[j]) continue;
      const bool apart = rects[i].x + rects[i].width <= rects[j].x || rects[j].x + rects[j].width <= rects[i].x ||
                         rects[i].y + rects[i].height <= rects[j].y || rects[j].y + rects[j].height <= rects[i].y;
      EXPECT_TRUE(apart) << i << " overlaps " << j;
    }
  }
}

TEST(Atlas, OversizedRectangleThrows) {
  std::vector<Rect> rects(1);
  rects[0].width = 600;
  rects[0].height = 10;
  int pages = 0;
  EXPECT_THROW(pack_shelves(rects, 512, 512, &pages), std::invalid_argument);
}

}  // namespace
}  // namespace hos::texture
