#include "pipeline/pipeline_config.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "core/error.h"
#include "pipeline/stages.h"

namespace hos::pipeline {
namespace {

std::string closest_of(const std::string& key, const std::vector<std::string>& names) {
  std::string best;
  std::size_t best_distance = std::string::npos;
  for (const auto& n : names) {
    const std::size_t d = edit_distance(key, n);
    if (d < best_distance) {
      best_distance = d;
      best = n;
    }
  }
  return best;
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

}  // namespace

PipelineConfig::PipelineConfig() {
  for (const auto& stage : pipeline_stage_names()) {
    stages_.emplace(stage, make_stage_config(stage));
  }
}

std::vector<std::string> PipelineConfig::available_stages() const {
  std::vector<std::string> out;
  for (const auto& stage : pipeline_stage_names()) {
    if (has_stage(stage)) out.push_back(stage);
  }
  return out;
}

void PipelineConfig::apply_root(const YAML::Node& root, const std::string& source) {
  if (!root || root.IsNull()) return;
  if (!root.IsMap()) {
    throw ConfigError(source, "must be a map of stage sections (" + stage_names_text(":, ") + ":)");
  }
  for (const auto& item : root) {
    const std::string section = item.first.Scalar();
    const auto& names = pipeline_stage_names();
    if (std::find(names.begin(), names.end(), section) == names.end()) {
      throw ConfigError(section, "unknown section (in " + source + ", line " +
                                     std::to_string(item.first.Mark().line + 1) + "); did you mean " +
                                     closest_of(section, names) + "? Sections: " + joined(names));
    }
    // A stage that is not built cannot check its keys; it will not run either.
    if (!has_stage(section)) continue;
    stages_.at(section)->option_set().apply_yaml(item.second, source);
  }
}

void PipelineConfig::apply_preset(const std::string& name_or_file) {
  const std::string text = builtin_preset_text(name_or_file);
  if (!text.empty()) {
    YAML::Node root;
    try {
      root = YAML::Load(text);
    } catch (const YAML::Exception& e) {
      throw ConfigError("--preset " + name_or_file, "built-in preset is not valid YAML: " + e.msg);
    }
    apply_root(root, "preset " + name_or_file);
    return;
  }
  const bool looks_like_file = name_or_file.find('/') != std::string::npos ||
                               name_or_file.find(".yaml") != std::string::npos ||
                               name_or_file.find(".yml") != std::string::npos;
  if (!looks_like_file) {
    throw ConfigError("--preset " + name_or_file,
                      "no such preset; the presets are: " + joined(builtin_preset_names()) + " (or give a YAML file)");
  }
  if (!std::filesystem::exists(name_or_file)) {
    throw ConfigError("--preset " + name_or_file, "preset file does not exist");
  }
  apply_file(name_or_file);
}

void PipelineConfig::apply_file(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(path, "config file does not exist");
  apply_root(load_yaml_file(path), path);
}

void PipelineConfig::apply_assignment(const std::string& assignment) {
  const auto eq = assignment.find('=');
  const auto dot = assignment.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot > eq) {
    throw ConfigError(assignment, "--set expects stage.key=value, e.g. --set recon.lambda=0.2");
  }
  const std::string stage = assignment.substr(0, dot);
  const std::string key = assignment.substr(dot + 1, eq - dot - 1);
  const auto& names = pipeline_stage_names();
  if (std::find(names.begin(), names.end(), stage) == names.end()) {
    throw ConfigError(stage,
                      "unknown stage in --set " + assignment + "; did you mean " + closest_of(stage, names) + "?");
  }
  if (!has_stage(stage)) {
    throw ConfigError(assignment, "the " + stage + " stage is not part of this build");
  }
  stages_.at(stage)->option_set().apply_assignment(key, assignment.substr(eq + 1), "--set");
}

void PipelineConfig::validate() const {
  for (const auto& [name, stage] : stages_) stage->validate();
}

std::string PipelineConfig::section_yaml(const std::string& stage) const {
  const auto it = stages_.find(stage);
  if (it == stages_.end()) return {};
  YAML::Emitter out;
  out << it->second->option_set().to_yaml();
  return out.c_str();
}

std::string PipelineConfig::resolved_yaml() const {
  std::ostringstream s;
  s << "# Resolved configuration of this run (defaults, preset, --config, --set).\n";
  for (const auto& stage : available_stages()) {
    YAML::Node root;
    root[stage] = stages_.at(stage)->option_set().to_yaml();
    YAML::Emitter out;
    out << root;
    s << out.c_str() << "\n";
  }
  return s.str();
}

std::string default_config_text() {
  std::ostringstream s;
  s << "# hos default configuration: every option of every stage with its default.\n"
       "# Generated by `hos-pipeline --print-default-config`; do not edit by hand.\n"
       "# Use it as a starting point for --config FILE; --set stage.key=value\n"
       "# overrides single options. Presets: config/presets/.\n";
  for (const auto& stage : pipeline_stage_names()) {
    s << "\n" << make_stage_config(stage)->option_set().documented_yaml();
  }
  return s.str();
}

}  // namespace hos::pipeline
