#include "core/text.h"

#include <gtest/gtest.h>

namespace hos {
namespace {

TEST(Text, LowerCaseChangesOnlyAsciiLetters) {
  EXPECT_EQ(lower_case("IMG_0001.JPG"), "img_0001.jpg");
  EXPECT_EQ(lower_case("a-Z 9\xC3\x89"), "a-z 9\xC3\x89") << "bytes of UTF-8 stay as they are";
}

TEST(Text, LowerCaseExtensionKeepsTheDot) {
  EXPECT_EQ(lower_case_extension("photos/A.HeIc"), ".heic");
  EXPECT_EQ(lower_case_extension("clip.tar.MP4"), ".mp4");
  EXPECT_EQ(lower_case_extension("README"), "");
}

}  // namespace
}  // namespace hos
