// Error types shared by every hos library. Libraries throw; only the stage
// mains catch, and they map each type to a documented exit code (exit_codes.h).
#pragma once

#include <stdexcept>
#include <string>

namespace hos {

// Base of all hos errors; what() is a complete sentence for the user.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A file or folder given to hos is missing, unreadable or malformed.
// what() reads "<path>: <reason>".
class InputError : public Error {
 public:
  InputError(std::string path, std::string reason);
  const std::string& path() const { return path_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string path_;
  std::string reason_;
};

// An option has an unknown key, a wrong type or an out-of-range value.
// what() reads "<key> = <value>: <reason>" (plus the file and line if known).
class ConfigError : public Error {
 public:
  ConfigError(std::string key, const std::string& reason);
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

// A computation produced NaN/Inf or failed to converge where that is fatal.
class NumericalError : public Error {
 public:
  NumericalError(const std::string& stage, const std::string& what);
};

// An output could not be written.
class OutputError : public Error {
 public:
  OutputError(const std::string& path, const std::string& reason);
};

// A stage failed for a reason that is not bad input (e.g. COLMAP registered
// too few images, an external tool crashed).
class StageError : public Error {
 public:
  StageError(const std::string& stage, const std::string& reason);
};

// The user asked to stop (SIGINT/SIGTERM) and the work stopped cleanly.
class Cancelled : public Error {
 public:
  Cancelled() : Error("interrupted by the user") {}
};

}  // namespace hos
