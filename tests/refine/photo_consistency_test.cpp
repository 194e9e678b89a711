#include "refine/photo_consistency.h"

#include <gtest/gtest.h>

namespace hos::refine {
namespace {

// ZNCC must not see a photo's exposure (gain and offset), and must refuse flat patches.
TEST(Zncc, IgnoresGainAndOffsetAndRefusesFlatPatches) {
  std::vector<float> a, brighter, reversed, flat(9, 0.5f);
  for (int i = 0; i < 9; ++i) {
    a.push_back(0.1f * static_cast<float>((i * 7) % 9));
    brighter.push_back(1.3f * a.back() + 0.05f);
    reversed.push_back(1.0f - a.back());
  }
  EXPECT_NEAR(*zncc(a, brighter, 0.01f), 1.0f, 1e-5f);
  EXPECT_NEAR(*zncc(a, reversed, 0.01f), -1.0f, 1e-5f);
  EXPECT_FALSE(zncc(a, flat, 0.01f).has_value());
}

}  // namespace
}  // namespace hos::refine
