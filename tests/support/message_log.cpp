#include "tests/support/message_log.h"

namespace hos::testing {

void MessageLog::log(LogLevel level, std::string_view message) {
  const std::lock_guard<std::mutex> lock(mutex_);
  messages_.emplace_back(level, std::string(message));
}

std::string MessageLog::warnings() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::string out;
  for (const auto& [level, text] : messages_) {
    if (level == LogLevel::kWarning) out += text + "\n";
  }
  return out;
}

std::string MessageLog::all() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::string out;
  for (const auto& [level, text] : messages_) out += text + "\n";
  return out;
}

}  // namespace hos::testing
