// How a stage that failed is reported, the same whichever executor ran it:
// its exit code becomes the error of the same kind, so hos-pipeline exits
// with the code that names the cause.
#pragma once

#include <filesystem>
#include <string>

namespace hos::pipeline {

// Throws the error a stage's exit code names (ConfigError for 2, InputError
// for 3 with input_hint, OutputError for 5, Cancelled for 130, StageError
// otherwise), naming its log.
[[noreturn]] void throw_stage_failure(const std::string& stage,
                                      int code,
                                      const std::filesystem::path& log,
                                      const std::string& input_hint);

}  // namespace hos::pipeline
