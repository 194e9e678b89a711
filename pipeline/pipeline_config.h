// The pipeline's configuration: every stage's options, resolved from the
// defaults, a preset, a YAML file and --set overrides (in that order).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "pipeline/stage_config.h"

namespace hos::pipeline {

class PipelineConfig {
 public:
  // Defaults of every stage built into this executable.
  PipelineConfig();

  // A built-in preset name ("fast", "default", "quality") or a YAML file.
  // Throws ConfigError for an unknown preset (listing the valid ones).
  void apply_preset(const std::string& name_or_file);
  // A YAML file whose top-level keys are stage names. An unknown stage or key
  // throws ConfigError naming the key, file and line, and the closest valid one.
  void apply_file(const std::string& path);
  // "stage.key=value".
  void apply_assignment(const std::string& assignment);
  // Every stage's validate().
  void validate() const;

  bool has_stage(const std::string& stage) const { return stages_.count(stage) > 0; }
  // The stage's options (null when its library is not built).
  const StageConfig* stage_config(const std::string& stage) const {
    const auto it = stages_.find(stage);
    return it == stages_.end() ? nullptr : it->second.get();
  }
  // The stages whose options are known (their libraries are built).
  std::vector<std::string> available_stages() const;
  // The section as YAML text (its hash decides whether the stage re-runs).
  std::string section_yaml(const std::string& stage) const;
  // All sections: the resolved config written into the workspace.
  std::string resolved_yaml() const;

 private:
  void apply_root(const YAML::Node& root, const std::string& source);
  std::map<std::string, std::unique_ptr<StageConfig>> stages_;
};

// The options struct of stage (e.g. recon::ReconOptions for "recon"); null
// when the stage's library is not built.
template <typename Options>
const Options* stage_options(const PipelineConfig& config, const std::string& stage) {
  const auto* typed = dynamic_cast<const TypedStageConfig<Options>*>(config.stage_config(stage));
  return typed ? &typed->options() : nullptr;
}

// config/default.yaml: every option of every built stage with its default,
// allowed values and a one-line comment. Generated, never edited by hand.
std::string default_config_text();

// Names of the built-in presets.
std::vector<std::string> builtin_preset_names();
// The preset's YAML text; empty if there is no such preset.
std::string builtin_preset_text(const std::string& name);

}  // namespace hos::pipeline
