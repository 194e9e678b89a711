#include "core/reporter.h"

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>

#include "core/error.h"

namespace hos {
namespace {

const char* level_name(LogLevel level) {
  switch (level) {
    case LogLevel::kDebug:
      return "debug";
    case LogLevel::kInfo:
      return "info";
    case LogLevel::kWarning:
      return "warning";
    case LogLevel::kError:
      return "error";
  }
  return "";
}

std::string json_escape(std::string_view s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out += ' ';
    } else {
      out += c;
    }
  }
  return out;
}

std::string format_duration(double seconds) {
  const int s = static_cast<int>(seconds);
  std::ostringstream o;
  o << s / 60 << ':' << std::setw(2) << std::setfill('0') << s % 60;
  return o.str();
}

}  // namespace

void Reporter::throw_if_cancelled() const {
  if (cancel_requested()) throw Cancelled();
}

Reporter& null_reporter() {
  static Reporter silent;  // stateless, so sharing it is safe
  return silent;
}

ConsoleReporter::ConsoleReporter(ConsoleReporterOptions options, std::ostream* out)
    : options_(std::move(options)), out_(out ? out : &std::cerr) {
  if (options_.style == ProgressStyle::kAuto) {
    const bool tty = (out_ == &std::cerr && isatty(STDERR_FILENO)) || (out_ == &std::cout && isatty(STDOUT_FILENO));
    options_.style = tty ? ProgressStyle::kBar : ProgressStyle::kPlain;
  }
}

ConsoleReporter::~ConsoleReporter() {
  std::lock_guard lock(mutex_);
  clear_bar_locked();
}

void ConsoleReporter::open_log_file(const std::string& path) {
  std::lock_guard lock(mutex_);
  log_file_ = std::make_unique<std::ofstream>(path, std::ios::app);
  if (!*log_file_) throw OutputError(path, "cannot open log file");
}

void ConsoleReporter::begin(std::string_view step, std::int64_t total) {
  std::lock_guard lock(mutex_);
  clear_bar_locked();
  step_ = step;
  total_ = total;
  done_ = 0;
  step_start_ = std::chrono::steady_clock::now();
  last_draw_ = step_start_;
  if (log_file_) *log_file_ << "[" << options_.stage << "] begin " << step_ << " (" << total << ")\n";
  draw_locked(false);
}

void ConsoleReporter::advance(std::int64_t n) {
  std::lock_guard lock(mutex_);
  done_ += n;
  const auto now = std::chrono::steady_clock::now();
  const double since = std::chrono::duration<double>(now - last_draw_).count();
  const double period = options_.style == ProgressStyle::kBar ? 0.1 : options_.plain_interval_s;
  if (since >= period) {
    last_draw_ = now;
    draw_locked(false);
  }
}

void ConsoleReporter::end() {
  std::lock_guard lock(mutex_);
  if (step_.empty()) return;
  if (total_ > 0) done_ = std::max(done_, total_);
  draw_locked(true);
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - step_start_).count();
  if (log_file_) *log_file_ << "[" << options_.stage << "] end " << step_ << " " << elapsed << " s\n";
  step_.clear();
}

void ConsoleReporter::log(LogLevel level, std::string_view message) {
  std::lock_guard lock(mutex_);
  if (log_file_)
    *log_file_ << "[" << options_.stage << "] " << level_name(level) << ": " << message << "\n" << std::flush;
  if (level < options_.min_level) return;
  clear_bar_locked();
  if (options_.style == ProgressStyle::kJson) {
    *out_ << "{\"stage\":\"" << json_escape(options_.stage) << "\",\"level\":\"" << level_name(level)
          << "\",\"message\":\"" << json_escape(message) << "\"}\n";
  } else {
    *out_ << "[" << options_.stage << "] ";
    if (level >= LogLevel::kWarning) *out_ << level_name(level) << ": ";
    *out_ << message << "\n";
  }
  out_->flush();
  if (!step_.empty() && options_.style == ProgressStyle::kBar) draw_locked(false);
}

bool ConsoleReporter::cancel_requested() const { return options_.cancel_requested && options_.cancel_requested(); }

void ConsoleReporter::clear_bar_locked() {
  if (bar_visible_) {
    *out_ << "\r\033[K";
    bar_visible_ = false;
  }
}

void ConsoleReporter::draw_locked(bool final_line) {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - step_start_).count();
  switch (options_.style) {
    case ProgressStyle::kNone:
    case ProgressStyle::kAuto:
      return;
    case ProgressStyle::kJson:
      *out_ << "{\"stage\":\"" << json_escape(options_.stage) << "\",\"step\":\"" << json_escape(step_)
            << "\",\"done\":" << done_ << ",\"total\":" << total_ << ",\"elapsed_s\":" << std::fixed
            << std::setprecision(2) << elapsed << std::defaultfloat << "}\n";
      break;
    case ProgressStyle::kPlain:
      *out_ << "[" << options_.stage << "] " << step_ << " " << done_;
      if (total_ > 0) *out_ << "/" << total_ << " (" << (100 * done_ / total_) << "%)";
      *out_ << " " << std::fixed << std::setprecision(1) << elapsed << std::defaultfloat << " s\n";
      break;
    case ProgressStyle::kBar: {
      constexpr int kWidth = 30;
      const double fraction = total_ > 0 ? std::min(1.0, double(done_) / double(total_)) : 0.0;
      const int filled = static_cast<int>(fraction * kWidth);
      *out_ << "\r\033[K" << options_.stage << "  " << step_ << "  [" << std::string(filled, '#')
            << std::string(kWidth - filled, ' ') << "] " << done_;
      if (total_ > 0) *out_ << "/" << total_;
      *out_ << "  " << format_duration(elapsed);
      bar_visible_ = true;
      if (final_line) {
        *out_ << "\n";
        bar_visible_ = false;
      }
      break;
    }
  }
  out_->flush();
}

}  // namespace hos
