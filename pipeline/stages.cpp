#include "pipeline/stages.h"

#include "core/error.h"
#include "pipeline/stage_entries.h"

namespace hos::pipeline {

const std::vector<StageSpec>& pipeline_stages() {
  static const std::vector<StageSpec> kSpecs{sfm_stage(), mvs_stage(), recon_stage(), refine_stage(), texture_stage()};
  return kSpecs;
}

const StageSpec* find_stage(const std::string& name) {
  for (const StageSpec& spec : pipeline_stages()) {
    if (spec.name == name) return &spec;
  }
  return nullptr;
}

bool find_stage_job(const std::string& job, const StageSpec*& spec, StageJob& kind) {
  for (const StageSpec& s : pipeline_stages()) {
    spec = &s;
    if (job == s.name) {
      kind = StageJob::kWhole;
      return true;
    }
    if (!s.split) continue;
    if (job == s.name + "-" + s.split->part_name) {
      kind = StageJob::kPart;
      return true;
    }
    if (job == s.name + "-" + s.split->join_name) {
      kind = StageJob::kJoin;
      return true;
    }
  }
  spec = nullptr;
  return false;
}

std::size_t stage_index(const std::string& name, const std::string& flag) {
  const auto& specs = pipeline_stages();
  for (std::size_t i = 0; i < specs.size(); ++i) {
    if (specs[i].name == name) return i;
  }
  throw ConfigError(flag + " " + name, "unknown stage; the stages are: " + stage_names_text(", "));
}

std::string stage_names_text(const std::string& separator) {
  std::string text;
  for (const StageSpec& spec : pipeline_stages()) text += (text.empty() ? "" : separator) + spec.name;
  return text;
}

}  // namespace hos::pipeline
