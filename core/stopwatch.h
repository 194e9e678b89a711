// Elapsed wall time for the stages' reported step times.
#pragma once

#include <chrono>

namespace hos {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace hos
