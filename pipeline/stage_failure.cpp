#include "pipeline/stage_failure.h"

#include "core/error.h"
#include "core/exit_codes.h"

namespace hos::pipeline {

void throw_stage_failure(const std::string& stage,
                         int code,
                         const std::filesystem::path& log,
                         const std::string& input_hint) {
  const std::string where = "see " + log.string();
  switch (code) {
    case kExitUsage:
      throw ConfigError(stage, "the stage rejected its configuration; " + where);
    case kExitBadInput:
      throw InputError(stage, "the stage rejected its input; " + where + (input_hint.empty() ? "" : "; " + input_hint));
    case kExitOutputFailed:
      throw OutputError(stage, "the stage could not write its output; " + where);
    case kExitInterrupted:
      throw Cancelled();
    default:
      throw StageError(stage, "failed (exit code " + std::to_string(code) + "); " + where);
  }
}

}  // namespace hos::pipeline
