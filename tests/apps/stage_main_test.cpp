// Every option of every stage is checked the same way whether it comes from
// a YAML file, --set or a stage executable's short flag: one table, one range.
#include "apps/stage_main.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <CLI/CLI.hpp>
#include <limits>
#include <optional>

#include "core/error.h"
#include "core/exit_codes.h"
#include "mvs/mvs_options.h"
#include "pipeline/stages.h"
#include "recon/recon_options.h"
#include "texture/texture_options.h"

namespace hos::apps {
namespace {

// Values that are out of range, malformed or non-finite for most options,
// and some that are valid for many.
const std::vector<std::string> kProbeValues = {"nan", "inf",   "-1",     "0",   "1e-7", "0.5",
                                               "3",   "1e300", "-1e300", "abc", "2048", "true"};

// The section's options after `apply`, as YAML text, or the error message.
std::string outcome(const std::string& stage, const std::function<void(OptionSet&)>& apply) {
  const auto config = pipeline::pipeline_stages()[pipeline::stage_index(stage, "stage")].make_config();
  try {
    apply(config->option_set());
    config->validate();
  } catch (const ConfigError& e) {
    return std::string("refused: ") + e.what();
  }
  YAML::Emitter out;
  out << config->option_set().to_yaml();
  return out.c_str();
}

// The short flag of key, if the table gives it one that takes a value.
const OptionSet::Flag* value_flag(const OptionSet& set, const std::string& key) {
  for (const auto& flag : set.flags()) {
    if (flag.key == key && flag.fixed_value.empty()) return &flag;
  }
  return nullptr;
}

TEST(StageOptions, EveryRangeIsEnforcedAlikeFromYamlSetAndFlags) {
  int flags_checked = 0, refusals = 0;
  for (const auto& spec : pipeline::pipeline_stages()) {
    const auto defaults = spec.make_config();
    const OptionSet& table = defaults->option_set();
    for (const std::string& key : table.keys()) {
      for (const std::string& value : kProbeValues) {
        const std::string from_yaml = outcome(spec.name, [&](OptionSet& set) {
          YAML::Node node = YAML::Load("{}");
          node[key] = value;
          set.apply_yaml(node, "test.yaml");
        });
        const std::string from_set = outcome(spec.name, [&](OptionSet& set) {
          CommonStageFlags flags;
          std::string assignment = spec.name;
          assignment.append(".").append(key).append("=").append(value);
          flags.assignments = {assignment};
          apply_config_and_overrides(set, flags);
        });
        // The messages name the source; compare whether and what was refused.
        const auto verdict = [](const std::string& text) {
          return text.rfind("refused", 0) == 0 ? std::string("refused") : text;
        };
        EXPECT_EQ(verdict(from_yaml), verdict(from_set)) << spec.name << "." << key << " = " << value;
        if (verdict(from_set) == "refused") ++refusals;
        const OptionSet::Flag* flag = value_flag(table, key);
        if (!flag) continue;
        const std::string from_flag = outcome(spec.name, [&](OptionSet& set) {
          CLI::App app;
          CommonStageFlags flags;
          add_common_stage_flags(app, flags, set);
          std::vector<std::string> args = {"stage", flag->flag, value};
          std::vector<char*> argv;
          argv.reserve(args.size());
          for (auto& a : args) argv.push_back(a.data());
          app.parse(static_cast<int>(argv.size()), argv.data());
          apply_config_and_overrides(set, flags);
        });
        EXPECT_EQ(verdict(from_flag), verdict(from_set)) << flag->flag << " " << value;
        ++flags_checked;
      }
    }
  }
  EXPECT_GT(flags_checked, 0);
  EXPECT_GT(refusals, 0);
}

TEST(StageOptions, ValidateChecksValuesSetInCodeAgainstTheTable) {
  // A library user sets members directly; validate() holds them to the same ranges.
  recon::ReconOptions recon;
  EXPECT_NO_THROW(recon.validate());
  recon.resolution = 4;
  EXPECT_THROW(recon.validate(), ConfigError);
  recon.resolution = 64;
  recon.lambda = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(recon.validate(), ConfigError);
  mvs::MvsOptions mvs;
  mvs.min_consistent_views = 33;
  EXPECT_THROW(mvs.validate(), ConfigError);
  texture::TextureOptions texture;
  texture.image_format = "gif";
  EXPECT_THROW(texture.validate(), ConfigError);
}

// --print-config prints the values the stage would run with: after --set
// and the short flags; a refused value is a usage error, not a listing.
TEST(StageOptions, PrintConfigShowsTheValuesAfterSetAndFlags) {
  const auto print = [](std::vector<std::string> args, std::string& out) {
    mvs::MvsOptions options;
    OptionSet set("mvs");
    mvs::register_options(set, options);
    CLI::App app;
    CommonStageFlags flags;
    add_common_stage_flags(app, flags, set);
    args.insert(args.begin(), "hos-mvs");
    args.emplace_back("--print-config");
    std::vector<char*> argv;
    argv.reserve(args.size());
    for (auto& a : args) argv.push_back(a.data());
    ::testing::internal::CaptureStdout();
    ::testing::internal::CaptureStderr();
    const std::optional<int> code =
        parse_stage_command_line(app, static_cast<int>(argv.size()), argv.data(), flags, set);
    out = ::testing::internal::GetCapturedStdout() + ::testing::internal::GetCapturedStderr();
    return code;
  };
  std::string out;
  EXPECT_EQ(print({}, out), std::optional<int>(kExitSuccess));
  EXPECT_NE(out.find("max_image_size: 1280"), std::string::npos) << out;
  EXPECT_EQ(print({"--set", "mvs.max_image_size=640", "--set", "num_source_views=4"}, out),
            std::optional<int>(kExitSuccess));
  EXPECT_NE(out.find("max_image_size: 640"), std::string::npos) << out;
  EXPECT_NE(out.find("num_source_views: 4"), std::string::npos) << out;
  EXPECT_EQ(print({"--max-image-size", "2048"}, out), std::optional<int>(kExitSuccess));
  EXPECT_NE(out.find("max_image_size: 2048"), std::string::npos) << out;
  EXPECT_EQ(print({"--set", "mvs.max_image_size=abc"}, out), std::optional<int>(kExitUsage));
  EXPECT_NE(out.find("max_image_size"), std::string::npos) << out;
  EXPECT_EQ(out.find("coarse_image_size"), std::string::npos) << out;  // no listing
}

TEST(StageOptions, StageNamesComeFromTheOneList) {
  EXPECT_EQ(pipeline::stage_names_text(", "), "sfm, mvs, recon, refine, texture");
  EXPECT_THROW(pipeline::stage_index("mesh", "--from"), ConfigError);
}

}  // namespace
}  // namespace hos::apps
