// core/option_set.*: YAML and --set overrides with clear errors.
#include "core/option_set.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <fstream>

#include "core/error.h"
#include "tests/support/test_support.h"

namespace hos {
namespace {

struct Example {
  double lambda = 0.2;
  int resolution = 128;
  bool trim = true;
  std::string mode = "fast";
};

OptionSet example_set(Example& e) {
  OptionSet set("recon");
  set.add("lambda", e.lambda, "weight", 0.0, 10.0);
  set.add("solver.resolution", e.resolution, "cells", 8, 1024);
  set.add("trim", e.trim, "trim");
  set.add_choice("mode", e.mode, {"fast", "slow"}, "mode");
  return set;
}

TEST(OptionSet, AppliesNestedYamlAndAssignments) {
  Example e;
  OptionSet set = example_set(e);
  set.apply_yaml(YAML::Load("lambda: 0.5\nsolver:\n  resolution: 64\ntrim: false\n"), "a.yaml");
  EXPECT_DOUBLE_EQ(e.lambda, 0.5);
  EXPECT_EQ(e.resolution, 64);
  EXPECT_FALSE(e.trim);
  set.apply_assignment("mode", "slow");
  EXPECT_EQ(e.mode, "slow");
  const YAML::Node dumped = set.to_yaml();
  EXPECT_EQ(dumped["solver"]["resolution"].as<int>(), 64);
}

TEST(OptionSet, UnknownKeyNamesFileLineAndClosestKey) {
  hos::testing::TempDir dir;
  std::ofstream(dir / "c.yaml") << "lambda: 0.3\nlamda: 0.4\n";
  Example e;
  OptionSet set = example_set(e);
  try {
    set.apply_yaml(load_yaml_file((dir / "c.yaml").string()), (dir / "c.yaml").string());
    FAIL();
  } catch (const ConfigError& err) {
    const std::string what = err.what();
    EXPECT_NE(what.find("lamda"), std::string::npos) << what;
    EXPECT_NE(what.find("c.yaml"), std::string::npos) << what;
    EXPECT_NE(what.find("line 2"), std::string::npos) << what;
    EXPECT_NE(what.find("lambda"), std::string::npos) << what;
  }
}

TEST(OptionSet, BadValuesNameTheAllowedRange) {
  Example e;
  OptionSet set = example_set(e);
  try {
    set.apply_assignment("solver.resolution", "4096");
    FAIL();
  } catch (const ConfigError& err) {
    EXPECT_NE(std::string(err.what()).find("1024"), std::string::npos) << err.what();
  }
  EXPECT_THROW(set.apply_assignment("lambda", "abc"), ConfigError);
  EXPECT_THROW(set.apply_assignment("mode", "medium"), ConfigError);
  EXPECT_THROW(set.apply_assignment("trim", "maybe"), ConfigError);
  EXPECT_EQ(e.resolution, 128) << "a rejected value must not be applied";
}

TEST(OptionSet, MalformedYamlIsAConfigurationError) {
  testing::TempDir dir;
  std::ofstream(dir / "bad.yaml") << "recon:\n  lambda: [1, 2\n";
  try {
    load_yaml_file((dir / "bad.yaml").string());
    FAIL() << "no error";
  } catch (const ConfigError& e) {  // exit 2 like every other configuration error
    EXPECT_NE(std::string(e.what()).find("bad.yaml"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("line"), std::string::npos);
  }
}

TEST(OptionSet, DuplicateKeysAreRefusedNamingBothLines) {
  testing::TempDir dir;
  std::ofstream(dir / "twice.yaml") << "recon:\n  lambda: 0.5\n  resolution: 64\n  lambda: 0.7\n";
  try {
    load_yaml_file((dir / "twice.yaml").string());
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("lambda"), std::string::npos) << what;
    EXPECT_NE(what.find("lines 2 and 4"), std::string::npos) << what;
  }
  std::ofstream(dir / "sections.yaml") << "recon:\n  lambda: 0.5\nmvs: {}\nrecon:\n  resolution: 64\n";
  EXPECT_THROW(load_yaml_file((dir / "sections.yaml").string()), ConfigError);
}

}  // namespace
}  // namespace hos
