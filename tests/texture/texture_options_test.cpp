#include "texture/texture_options.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace hos::texture {
namespace {

TEST(TextureOptions, DefaultsAreValid) { EXPECT_NO_THROW(TextureOptions{}.validate()); }

TEST(TextureOptions, BadValuesThrowConfigError) {
  TextureOptions o;
  o.max_faces = 2;
  EXPECT_THROW(o.validate(), ConfigError);
  o = TextureOptions{};
  o.image_format = "gif";
  EXPECT_THROW(o.validate(), ConfigError);
  o = TextureOptions{};
  o.padding = 100;
  o.atlas_size = 128;
  EXPECT_THROW(o.validate(), ConfigError);
}

TEST(TextureOptions, KeysMapOntoFields) {
  TextureOptions o;
  OptionSet set("texture");
  register_options(set, o);
  set.apply_assignment("atlas_size", "2048");
  set.apply_assignment("image_format", "jpeg");
  set.apply_assignment("global_leveling", "false");
  EXPECT_EQ(o.atlas_size, 2048);
  EXPECT_EQ(o.image_format, "jpeg");
  EXPECT_FALSE(o.global_leveling);
  EXPECT_THROW(set.apply_assignment("atlas_size", "10"), ConfigError);
}

}  // namespace
}  // namespace hos::texture
