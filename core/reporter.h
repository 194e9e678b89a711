// Logging and progress reporting, injected into every library call.
// Libraries never print: they talk to a Reporter, and the executables decide
// where that goes (terminal bar, plain periodic lines, JSON lines, a log file).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <string_view>

namespace hos {

enum class LogLevel { kDebug = 0, kInfo = 1, kWarning = 2, kError = 3 };

// Base class: ignores everything and never cancels. Thread-safe for advance()
// and the log functions when overridden by the provided subclasses.
class Reporter {
 public:
  virtual ~Reporter() = default;

  // Starts a step of a stage with total work items (0 if unknown).
  virtual void begin(std::string_view /*step*/, std::int64_t /*total*/) {}
  // n more work items are done (callable from OpenMP threads).
  virtual void advance(std::int64_t /*n*/ = 1) {}
  // The current step is finished.
  virtual void end() {}
  virtual void log(LogLevel /*level*/, std::string_view /*message*/) {}

  // True once the user asked to stop. Long loops poll it between work items.
  virtual bool cancel_requested() const { return false; }
  // Throws Cancelled if cancel_requested().
  void throw_if_cancelled() const;

  void debug(std::string_view m) { log(LogLevel::kDebug, m); }
  void info(std::string_view m) { log(LogLevel::kInfo, m); }
  void warn(std::string_view m) { log(LogLevel::kWarning, m); }
  void error(std::string_view m) { log(LogLevel::kError, m); }
};

// The silent default for tests and library users who want no output.
Reporter& null_reporter();

// How ConsoleReporter renders progress.
enum class ProgressStyle {
  kAuto,   // bar on a terminal, plain lines otherwise
  kBar,    // one redrawn line: "mvs  depth maps  [#####     ] 12/24  0:41"
  kPlain,  // a line every few seconds: "mvs depth maps 12/24 (50%) 41.2 s"
  kJson,   // one JSON object per line: {"stage":..,"step":..,"done":..,"total":..,"elapsed_s":..}
  kNone,
};

struct ConsoleReporterOptions {
  std::string stage;  // prefix of every line, e.g. "recon"
  ProgressStyle style = ProgressStyle::kAuto;
  LogLevel min_level = LogLevel::kInfo;
  double plain_interval_s = 5.0;           // period of plain progress lines
  std::function<bool()> cancel_requested;  // e.g. a signal flag; may be empty
};

// Writes progress and messages to a stream (stderr by default) and,
// optionally, every message at any level to a log file.
class ConsoleReporter : public Reporter {
 public:
  explicit ConsoleReporter(ConsoleReporterOptions options, std::ostream* out = nullptr);
  ~ConsoleReporter() override;

  // Also append all messages (debug included) to this file.
  void open_log_file(const std::string& path);

  void begin(std::string_view step, std::int64_t total) override;
  void advance(std::int64_t n = 1) override;
  void end() override;
  void log(LogLevel level, std::string_view message) override;
  bool cancel_requested() const override;

 private:
  void draw_locked(bool final_line);
  void clear_bar_locked();

  ConsoleReporterOptions options_;
  std::ostream* out_;
  std::unique_ptr<std::ofstream> log_file_;
  std::mutex mutex_;
  std::string step_;
  std::int64_t total_ = 0;
  std::int64_t done_ = 0;
  bool bar_visible_ = false;
  std::chrono::steady_clock::time_point step_start_;
  std::chrono::steady_clock::time_point last_draw_;
};

// Builds a message from streamable parts: format_message("read ", n, " points").
template <typename... Parts>
std::string format_message(const Parts&... parts) {
  std::ostringstream s;
  (s << ... << parts);
  return s.str();
}

}  // namespace hos
