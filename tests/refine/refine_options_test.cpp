#include "refine/refine_options.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/option_set.h"

namespace hos::refine {
namespace {

TEST(RefineOptions, DefaultsAreValidAndEveryFieldHasAKey) {
  RefineOptions options;
  EXPECT_NO_THROW(options.validate());
  OptionSet set("refine");
  register_options(set, options);
  set.apply_assignment("regularizer", "membrane");
  set.apply_assignment("enabled", "true");
  EXPECT_EQ(options.regularizer, Regularizer::kMembrane);
  EXPECT_TRUE(options.enabled);
  EXPECT_THROW(set.apply_assignment("regularizer", "bending"), ConfigError);
  EXPECT_THROW(set.apply_assignment("levels", "0"), ConfigError);
}

TEST(RefineOptions, ValidateNamesTheOption) {
  RefineOptions options;
  options.patch_size = 4;
  try {
    options.validate();
    FAIL() << "an even patch was accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "refine.patch_size");
  }
  options = RefineOptions{};
  options.min_angle_deg = 70.0;  // above max_angle_deg
  EXPECT_THROW(options.validate(), ConfigError);
}

}  // namespace
}  // namespace hos::refine
