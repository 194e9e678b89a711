// A Reporter that keeps the messages, for tests of what the user is told.
#pragma once

#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "core/reporter.h"

namespace hos::testing {

class MessageLog : public Reporter {
 public:
  void log(LogLevel level, std::string_view message) override;
  // Every warning, one per line.
  std::string warnings() const;
  // Every message of any level, one per line.
  std::string all() const;

 private:
  mutable std::mutex mutex_;
  std::vector<std::pair<LogLevel, std::string>> messages_;
};

}  // namespace hos::testing
