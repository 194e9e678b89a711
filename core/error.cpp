#include "core/error.h"

namespace hos {

InputError::InputError(std::string path, std::string reason)
    : Error(path + ": " + reason), path_(std::move(path)), reason_(std::move(reason)) {}

ConfigError::ConfigError(std::string key, const std::string& reason)
    : Error(key + ": " + reason), key_(std::move(key)) {}

NumericalError::NumericalError(const std::string& stage, const std::string& what)
    : Error(stage + ": numerical failure: " + what) {}

OutputError::OutputError(const std::string& path, const std::string& reason)
    : Error(path + ": cannot write: " + reason) {}

StageError::StageError(const std::string& stage, const std::string& reason) : Error(stage + ": " + reason) {}

}  // namespace hos
