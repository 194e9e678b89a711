#include "pipeline/stage_config.h"

#include "pipeline/stages.h"

namespace hos::pipeline {

const std::vector<std::string>& pipeline_stage_names() {
  static const std::vector<std::string> kNames = [] {
    std::vector<std::string> names;
    for (const StageSpec& spec : pipeline_stages()) names.push_back(spec.name);
    return names;
  }();
  return kNames;
}

std::unique_ptr<StageConfig> make_stage_config(const std::string& stage) {
  return pipeline_stages()[stage_index(stage, "stage")].make_config();
}

}  // namespace hos::pipeline
