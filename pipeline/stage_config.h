// The options of one stage behind a common interface, so the driver can load,
// validate, print and hash every stage's YAML section without knowing the
// stage's options struct. Stages whose library is not built have no config.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/option_set.h"

namespace hos::pipeline {

class StageConfig {
 public:
  virtual ~StageConfig() = default;
  virtual OptionSet& option_set() = 0;
  virtual const OptionSet& option_set() const = 0;
  // The options struct's validate(): throws ConfigError.
  virtual void validate() const = 0;
};

// Owns an options struct and the OptionSet that points into it (hence not
// copyable or movable: the set holds references to the members).
template <typename Options>
class TypedStageConfig final : public StageConfig {
 public:
  explicit TypedStageConfig(const std::string& section) : set_(section) { register_options(set_, options_); }
  TypedStageConfig(const TypedStageConfig&) = delete;
  TypedStageConfig& operator=(const TypedStageConfig&) = delete;
  OptionSet& option_set() override { return set_; }
  const OptionSet& option_set() const override { return set_; }
  void validate() const override { options_.validate(); }
  const Options& options() const { return options_; }

 private:
  Options options_;
  OptionSet set_;
};

// The pipeline's stages in order.
const std::vector<std::string>& pipeline_stage_names();

// A fresh config with defaults for stage (throws ConfigError for an unknown
// stage name).
std::unique_ptr<StageConfig> make_stage_config(const std::string& stage);

}  // namespace hos::pipeline
