// synth/synth_options.*: hos-synth's table holds the ranges; validate() the
// rules between options.
#include "synth/synth_options.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace hos::synth {
namespace {

// The ConfigError's key when key=value is applied, or "<accepted>".
std::string refused_key(const std::string& key, const std::string& value) {
  SceneOptions scene;
  DatasetOptions dataset;
  VideoOptions video;
  OptionSet set("synth");
  register_options(set, scene);
  register_options(set, dataset);
  register_options(set, video);
  try {
    set.apply_assignment(key, value);
  } catch (const ConfigError& e) {
    return e.key();
  }
  return "<accepted>";
}

TEST(SynthOptions, TheTableRefusesValuesOutsideTheirRanges) {
  EXPECT_EQ(refused_key("views", "1"), "synth.views");
  EXPECT_EQ(refused_key("views", "2"), "<accepted>");
  EXPECT_EQ(refused_key("width", "15"), "synth.width");
  EXPECT_EQ(refused_key("supersampling", "9"), "synth.supersampling");
  EXPECT_EQ(refused_key("tilt_deg", "-60.5"), "synth.tilt_deg");
  EXPECT_EQ(refused_key("tilt_deg", "-60"), "<accepted>");
  EXPECT_EQ(refused_key("scene", "teapot"), "synth.scene");
  EXPECT_EQ(refused_key("seed", "-1"), "synth.seed");
  EXPECT_EQ(refused_key("video.frames", "2"), "synth.video.frames");
  EXPECT_EQ(refused_key("metres_per_unit", "0"), "synth.metres_per_unit");
}

TEST(SynthOptions, ValidateChecksTheTableAndTheRulesBetweenOptions) {
  EXPECT_NO_THROW(DatasetOptions{}.validate());
  EXPECT_NO_THROW(SceneOptions{}.validate());
  EXPECT_NO_THROW(VideoOptions{}.validate());
  DatasetOptions dataset;
  dataset.focal = -1.0;  // set in code: held to the table's range
  EXPECT_THROW(dataset.validate(), ConfigError);
  dataset = DatasetOptions{};
  dataset.exposure_gains = {1.0f, 1.1f};  // not one per view
  EXPECT_THROW(dataset.validate(), ConfigError);
  dataset = DatasetOptions{};
  dataset.gps_origin = GeoPosition{46.0, 7.0, 500.0};  // GPS needs JPEG
  EXPECT_THROW(dataset.validate(), ConfigError);
  dataset.jpeg = true;
  EXPECT_NO_THROW(dataset.validate());
  VideoOptions video;
  video.fps = 0.0;
  EXPECT_THROW(video.validate(), ConfigError);
}

}  // namespace
}  // namespace hos::synth
