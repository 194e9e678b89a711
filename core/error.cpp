#include "core/error.h"

namespace hos {

InputError::InputError(std::string path, std::string reason)
    : Error(path + ": " + reason), path_(std::move(path)), reason_(std::move(reason)) {}

ConfigError::ConfigError(std::string key, std::string reason) : Error(key + ": " + reason), key_(std::move(key)) {}

NumericalError::NumericalError(std::string stage, std::string what) : Error(stage + ": numerical failure: " + what) {}

OutputError::OutputError(std::string path, std::string reason) : Error(path + ": cannot write: " + reason) {}

StageError::StageError(std::string stage, std::string reason) : Error(stage + ": " + reason) {}

}  // namespace hos
