#include "pipeline/pipeline_config.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "tests/support/test_support.h"

namespace hos::pipeline {
namespace {
using ::testing::HasSubstr;

std::string config_error(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "<no ConfigError>";
}

TEST(PipelineConfig, UnknownKeyNamesFileLineAndClosestKey) {
  hos::testing::TempDir dir;
  std::ofstream(dir / "c.yaml") << "sfm:\n  matcher: exhaustive\n  max_imge_size: 100\n";
  PipelineConfig config;
  const std::string message = config_error([&] { config.apply_file((dir / "c.yaml").string()); });
  EXPECT_THAT(message, HasSubstr("sfm.max_imge_size"));
  EXPECT_THAT(message, HasSubstr("c.yaml, line 3"));
  EXPECT_THAT(message, HasSubstr("did you mean sfm.max_image_size"));
}

TEST(PipelineConfig, UnknownSectionNamesClosestStage) {
  hos::testing::TempDir dir;
  std::ofstream(dir / "c.yaml") << "sfm:\n  matcher: auto\nrecn:\n  lambda: 0.2\n";
  PipelineConfig config;
  const std::string message = config_error([&] { config.apply_file((dir / "c.yaml").string()); });
  EXPECT_THAT(message, HasSubstr("recn"));
  EXPECT_THAT(message, HasSubstr("line 3"));
  EXPECT_THAT(message, HasSubstr("did you mean recon"));
}

TEST(PipelineConfig, OutOfRangeValueNamesRange) {
  PipelineConfig config;
  const std::string message = config_error([&] { config.apply_assignment("sfm.max_image_size=-5"); });
  EXPECT_THAT(message, HasSubstr("[0, 100000]"));
  EXPECT_THAT(config_error([&] { config.apply_assignment("sfmmatcher=auto"); }), HasSubstr("stage.key=value"));
  EXPECT_THAT(config_error([&] { config.apply_assignment("sfn.matcher=auto"); }), HasSubstr("did you mean sfm"));
}

TEST(PipelineConfig, LaterSourcesOverrideEarlierOnes) {
  hos::testing::TempDir dir;
  std::ofstream(dir / "c.yaml") << "sfm:\n  max_num_features: 5000\n  matcher: sequential\n";
  PipelineConfig config;
  config.apply_preset("fast");
  EXPECT_THAT(config.section_yaml("sfm"), HasSubstr("max_num_features: 2048"));
  config.apply_file((dir / "c.yaml").string());
  config.apply_assignment("sfm.max_num_features=6000");
  const std::string sfm = config.section_yaml("sfm");
  EXPECT_THAT(sfm, HasSubstr("max_num_features: 6000"));
  EXPECT_THAT(sfm, HasSubstr("matcher: sequential"));
  EXPECT_THAT(sfm, HasSubstr("max_image_size: 1600"));  // from the preset, untouched
  EXPECT_THAT(config.resolved_yaml(), HasSubstr("sfm:"));
}

TEST(PipelineConfig, MissingPresetListsTheValidOnes) {
  PipelineConfig config;
  const std::string message = config_error([&] { config.apply_preset("fastest"); });
  EXPECT_THAT(message, HasSubstr("fast, default, quality"));
  EXPECT_THAT(config_error([&] { config.apply_preset("nope/preset.yaml"); }), HasSubstr("does not exist"));
}

TEST(PipelineConfig, EveryBuiltinPresetAppliesAndValidates) {
  for (const auto& name : builtin_preset_names()) {
    PipelineConfig config;
    EXPECT_NO_THROW(config.apply_preset(name)) << name;
    EXPECT_NO_THROW(config.validate()) << name;
  }
}

TEST(PipelineConfig, ResolvedConfigReadsBackUnchanged) {
  hos::testing::TempDir dir;
  PipelineConfig config;
  config.apply_preset("quality");
  config.apply_assignment("sfm.matcher=sequential");
  std::ofstream(dir / "resolved.yaml") << config.resolved_yaml();
  PipelineConfig reread;
  reread.apply_file((dir / "resolved.yaml").string());
  for (const auto& stage : config.available_stages()) {
    EXPECT_EQ(reread.section_yaml(stage), config.section_yaml(stage)) << stage;
  }
}

TEST(PipelineConfig, NestedAliasesAreRefusedAtOnce) {
  hos::testing::TempDir dir;
  // 9^9 values from a few hundred bytes: refused before anything walks them.
  std::string yaml = "recon:\n  a: &a [x, x, x, x, x, x, x, x, x]\n";
  std::string before = "a";
  for (const std::string name : {"b", "c", "d", "e", "f", "g", "h", "i"}) {
    yaml.append("  ").append(name).append(": &").append(name).append(" [*").append(before);
    for (int i = 1; i < 9; ++i) yaml += ", *" + before;
    yaml += "]\n";
    before = name;
  }
  std::ofstream(dir / "c.yaml") << yaml;
  PipelineConfig config;
  const auto start = std::chrono::steady_clock::now();
  const std::string message = config_error([&] { config.apply_file((dir / "c.yaml").string()); });
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 0.5);
  EXPECT_THAT(message, HasSubstr("c.yaml"));
  EXPECT_THAT(message, HasSubstr("aliases"));
}

TEST(PipelineConfig, ASecondDocumentIsRefused) {
  hos::testing::TempDir dir;
  std::ofstream(dir / "c.yaml") << "sfm:\n  matcher: exhaustive\n---\nrecon:\n  lambda: 0.3\n";
  PipelineConfig config;
  const std::string message = config_error([&] { config.apply_file((dir / "c.yaml").string()); });
  EXPECT_THAT(message, HasSubstr("second YAML document"));
  EXPECT_THAT(message, HasSubstr("line 4"));
}

TEST(PipelineConfig, SignedNumbersApplyAndUnderflowIsNamed) {
  hos::testing::TempDir dir;
  std::ofstream(dir / "c.yaml") << "recon:\n  lambda: +0.3\n";
  PipelineConfig config;
  config.apply_file((dir / "c.yaml").string());
  EXPECT_THAT(config.section_yaml("recon"), HasSubstr("lambda: 0.3"));
  std::ofstream(dir / "tiny.yaml") << "recon:\n  lambda: 1e-400\n";
  const std::string message = config_error([&] { config.apply_file((dir / "tiny.yaml").string()); });
  EXPECT_THAT(message, HasSubstr("recon.lambda"));
  EXPECT_THAT(message, HasSubstr("tiny.yaml, line 2"));
  EXPECT_THAT(message, HasSubstr("underflows"));
}

// Top-level sections of a config text: "name:" -> the lines under it.
std::map<std::string, std::string> sections(const std::string& text) {
  std::map<std::string, std::string> out;
  std::istringstream in(text);
  std::string current;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    if (line[0] != ' ') {
      current = line.substr(0, line.find(':'));
      continue;
    }
    out[current] += line + "\n";
  }
  return out;
}

TEST(PipelineConfig, CommittedDefaultConfigIsTheGeneratedOne) {
  std::ifstream in(hos::testing::source_dir() / "config" / "default.yaml");
  ASSERT_TRUE(in) << "config/default.yaml is missing";
  const std::string committed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto committed_sections = sections(committed);
  const auto generated_sections = sections(default_config_text());
  // Stages not built here cannot be checked; every built one must match.
  for (const auto& [stage, text] : generated_sections) {
    ASSERT_TRUE(committed_sections.count(stage))
        << "config/default.yaml has no " << stage
        << " section; regenerate it: hos-pipeline --print-default-config > config/default.yaml";
    EXPECT_EQ(committed_sections.at(stage), text) << "config/default.yaml is out of date; regenerate it: hos-pipeline "
                                                     "--print-default-config > config/default.yaml";
  }
  PipelineConfig config;
  EXPECT_NO_THROW(config.apply_file((hos::testing::source_dir() / "config" / "default.yaml").string()));
}

}  // namespace
}  // namespace hos::pipeline
