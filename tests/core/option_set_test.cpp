// core/option_set.*: YAML and --set overrides with clear errors.
#include "core/option_set.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <chrono>
#include <fstream>
#include <sstream>

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

// Levels of lists, each of nine aliases of the level before: 9^levels values.
std::string nested_aliases(int levels) {
  std::ostringstream yaml;
  yaml << "a0: &a0 [x, x, x, x, x, x, x, x, x]\n";
  for (int level = 1; level < levels; ++level) {
    yaml << "a" << level << ": &a" << level << " [*a" << level - 1;
    for (int i = 1; i < 9; ++i) yaml << ", *a" << level - 1;
    yaml << "]\n";
  }
  return yaml.str();
}

std::string config_error(const std::string& yaml) {
  testing::TempDir dir;
  std::ofstream(dir / "c.yaml") << yaml;
  try {
    load_yaml_file((dir / "c.yaml").string());
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "<no ConfigError>";
}

TEST(OptionSet, AliasesExpandingBeyondAnyConfigAreRefused) {
  // 9^5 values: more than a config could need, walked in no time.
  EXPECT_NE(config_error(nested_aliases(5)).find("aliases"), std::string::npos);
  // 9^9 (a file of about 300 bytes): refused, as fast.
  const auto start = std::chrono::steady_clock::now();
  const std::string message = config_error(nested_aliases(9));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_NE(message.find("c.yaml"), std::string::npos) << message;
  EXPECT_NE(message.find("aliases"), std::string::npos) << message;
  EXPECT_LT(seconds, 0.5);
}

TEST(OptionSet, AliasesOfSingleValuesStillApply) {
  testing::TempDir dir;
  std::ofstream(dir / "c.yaml") << "lambda: &weight 0.5\nsolver:\n  resolution: 64\nshared: *weight\n";
  const YAML::Node root = load_yaml_file((dir / "c.yaml").string());
  EXPECT_DOUBLE_EQ(root["shared"].as<double>(), 0.5);
}

TEST(OptionSet, ASecondDocumentIsRefusedAnEmptyOneIgnored) {
  const std::string message = config_error("lambda: 0.5\n---\nlambda: 0.7\n");
  EXPECT_NE(message.find("second YAML document"), std::string::npos) << message;
  EXPECT_NE(message.find("line 3"), std::string::npos) << message;
  EXPECT_EQ(config_error("lambda: 0.5\n---\n"), "<no ConfigError>");
}

TEST(OptionSet, NumbersWithAPlusParseAndUnderflowIsNamed) {
  Example e;
  OptionSet set = example_set(e);
  set.apply_assignment("lambda", "+0.3");
  EXPECT_DOUBLE_EQ(e.lambda, 0.3);
  set.apply_assignment("solver.resolution", "+64");
  EXPECT_EQ(e.resolution, 64);
  auto message = [&](const std::string& key, const std::string& value) {
    try {
      set.apply_assignment(key, value);
    } catch (const ConfigError& error) {
      return std::string(error.what());
    }
    return std::string("<no ConfigError>");
  };
  EXPECT_NE(message("lambda", "1e-400").find("underflows"), std::string::npos) << message("lambda", "1e-400");
  EXPECT_NE(message("lambda", "1e400").find("overflows"), std::string::npos);
  EXPECT_NE(message("lambda", "1e-99999").find("underflows"), std::string::npos) << "beyond even a long double";
  EXPECT_NE(message("lambda", "-1e99999").find("overflows"), std::string::npos);
  EXPECT_NE(message("lambda", "+-1").find("is not a number"), std::string::npos);
  EXPECT_NE(message("lambda", "abc").find("is not a number"), std::string::npos);
  EXPECT_NE(message("solver.resolution", "64.5").find("is not an integer"), std::string::npos);
  EXPECT_NE(message("solver.resolution", "1e2").find("not written as an integer"), std::string::npos);
  EXPECT_NE(message("solver.resolution", "1e12").find("too large"), std::string::npos);
  EXPECT_DOUBLE_EQ(e.lambda, 0.3) << "a refused value must not be applied";
  EXPECT_EQ(parse_number<float>("1e-50"), std::nullopt);
  EXPECT_NE(number_problem<float>("1e-50").find("underflows"), std::string::npos);
  EXPECT_EQ(parse_number<double>("1e-320"), 1e-320) << "a subnormal double is a number";
}

struct Ranges {
  int features = 0;
  double voxel = 0.5;
  int patch = 7;
};

OptionSet ranges_set(Ranges& r) {
  OptionSet set("sfm");
  set.add_zero_or("features", r.features, "features; 0 = auto", 100, 100000);
  set.add_zero_or("voxel", r.voxel, "voxel; 0 = off", 0.25, 4.0);
  set.add_odd("patch", r.patch, "patch side", 3, 15);
  return set;
}

// The ConfigError's text when key=value is applied, or "<no ConfigError>".
std::string assignment_error(OptionSet& set, const std::string& key, const std::string& value) {
  try {
    set.apply_assignment(key, value);
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "<no ConfigError>";
}

TEST(OptionSet, ZeroOrARangeTakesZeroAndTheRangeOnly) {
  Ranges r;
  OptionSet set = ranges_set(r);
  for (const char* allowed : {"0", "100", "4096", "100000"}) {
    EXPECT_EQ(assignment_error(set, "features", allowed), "<no ConfigError>") << allowed;
  }
  EXPECT_EQ(r.features, 100000);
  for (const char* refused : {"1", "99", "-100", "100001"}) {
    const std::string message = assignment_error(set, "features", refused);
    EXPECT_NE(message.find("sfm.features"), std::string::npos) << message;
    EXPECT_NE(message.find("0 or an integer in [100, 100000]"), std::string::npos) << message;
  }
  EXPECT_EQ(r.features, 100000) << "a refused value must not be applied";
  EXPECT_EQ(assignment_error(set, "voxel", "0"), "<no ConfigError>");
  EXPECT_DOUBLE_EQ(r.voxel, 0.0);
  EXPECT_EQ(assignment_error(set, "voxel", "0.25"), "<no ConfigError>");
  EXPECT_NE(assignment_error(set, "voxel", "0.1").find("0 or a number in [0.25, 4]"), std::string::npos);
  EXPECT_NE(assignment_error(set, "voxel", "nan").find("sfm.voxel"), std::string::npos);
  EXPECT_DOUBLE_EQ(r.voxel, 0.25);
}

TEST(OptionSet, OddTakesOddValuesInItsRangeOnly) {
  Ranges r;
  OptionSet set = ranges_set(r);
  EXPECT_EQ(assignment_error(set, "patch", "3"), "<no ConfigError>");
  EXPECT_EQ(assignment_error(set, "patch", "15"), "<no ConfigError>");
  for (const char* refused : {"4", "14", "1", "17", "-3"}) {
    const std::string message = assignment_error(set, "patch", refused);
    EXPECT_NE(message.find("sfm.patch"), std::string::npos) << message;
    EXPECT_NE(message.find("an odd integer in [3, 15]"), std::string::npos) << message;
  }
  EXPECT_EQ(r.patch, 15);
}

TEST(OptionSet, ZeroOrAndOddApplyToYamlValuesSetInCodeAndTheDocumentation) {
  Ranges r;
  OptionSet set = ranges_set(r);
  EXPECT_THROW(set.apply_yaml(YAML::Load("features: 50\n"), "a.yaml"), ConfigError);
  EXPECT_THROW(set.apply_yaml(YAML::Load("patch: 8\n"), "a.yaml"), ConfigError);
  set.apply_yaml(YAML::Load("features: 0\npatch: 9\n"), "a.yaml");
  EXPECT_EQ(r.patch, 9);
  EXPECT_NO_THROW(set.check_values());
  r.features = 50;  // set in code, as a library user would
  EXPECT_THROW(set.check_values(), ConfigError);
  r.features = 0;
  r.patch = 6;
  try {
    set.check_values();
    FAIL() << "an even patch passed";
  } catch (const ConfigError& error) {
    EXPECT_EQ(error.key(), "sfm.patch");
  }
  EXPECT_EQ(set.documentation("features"), "features; 0 = auto [0 or an integer in [100, 100000]]");
  EXPECT_EQ(set.documentation("patch"), "patch side [an odd integer in [3, 15]]");
  EXPECT_NE(set.documented_yaml().find("  patch: 6  # patch side [an odd integer in [3, 15]]\n"), std::string::npos)
      << set.documented_yaml();
}

TEST(OptionSet, CountsTakeNoNegativeValue) {
  std::size_t samples = 200000;
  OptionSet set("eval");
  set.add("samples", samples, "samples", std::size_t{1000}, std::size_t{1000000000});
  EXPECT_EQ(assignment_error(set, "samples", "5000"), "<no ConfigError>");
  EXPECT_EQ(samples, 5000u);
  EXPECT_NE(assignment_error(set, "samples", "-5000").find("is negative"), std::string::npos);
  EXPECT_NE(assignment_error(set, "samples", "999").find("an integer in [1000, 1000000000]"), std::string::npos);
  EXPECT_EQ(samples, 5000u);
}

}  // namespace
}  // namespace hos
