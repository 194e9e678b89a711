#include "core/subprocess.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <map>

#include "core/error.h"
#include "core/reporter.h"

namespace hos {
namespace {

bool is_executable_file(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(path.c_str(), X_OK) == 0;
}

// The child's environment: ours plus the requested overrides.
std::vector<std::string> child_environment(const std::vector<std::pair<std::string, std::string>>& overrides) {
  std::map<std::string, std::string> vars;
  for (char** e = environ; e && *e; ++e) {
    const std::string entry(*e);
    const auto eq = entry.find('=');
    if (eq != std::string::npos) vars[entry.substr(0, eq)] = entry.substr(eq + 1);
  }
  for (const auto& [key, value] : overrides) vars[key] = value;
  std::vector<std::string> out;
  out.reserve(vars.size());
  for (const auto& [key, value] : vars) out.emplace_back(key).append("=").append(value);
  return out;
}

std::vector<char*> c_strings(std::vector<std::string>& strings) {
  std::vector<char*> out;
  out.reserve(strings.size() + 1);
  for (auto& s : strings) out.push_back(s.data());
  out.push_back(nullptr);
  return out;
}

// Splits the byte stream into lines for the callback.
class LineSplitter {
 public:
  explicit LineSplitter(const std::function<void(std::string_view)>& sink) : sink_(sink) {}
  void feed(const char* data, std::size_t size) {
    for (std::size_t i = 0; i < size; ++i) {
      const char c = data[i];
      if (c == '\n' || c == '\r') {
        flush();
      } else {
        pending_ += c;
      }
    }
  }
  void flush() {
    if (!pending_.empty()) sink_(pending_);
    pending_.clear();
  }

 private:
  const std::function<void(std::string_view)>& sink_;
  std::string pending_;
};

double seconds_of(const timeval& t) { return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_usec) * 1e-6; }

}  // namespace

std::string find_executable(const std::string& program) {
  if (program.empty()) return {};
  if (program.find('/') != std::string::npos) return is_executable_file(program) ? program : std::string();
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/local/bin:/usr/bin:/bin";
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t end = std::min(dirs.find(':', start), dirs.size());
    const std::string dir = dirs.substr(start, end - start);
    std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + program;
    if (is_executable_file(candidate)) return candidate;
    start = end + 1;
  }
  return {};
}

namespace {

// The pipes between this process and the child: its output (when captured)
// and an exec failure's errno (closed on exec).
struct ChildPipes {
  int out[2] = {-1, -1};
  int exec[2] = {-1, -1};
};

ChildPipes open_pipes(const ProcessOptions& options, bool capture) {
  ChildPipes pipes;
  if ((capture && ::pipe2(pipes.out, O_CLOEXEC) != 0) || ::pipe2(pipes.exec, O_CLOEXEC) != 0) {
    throw StageError(options.argv[0], std::string("cannot create a pipe: ") + std::strerror(errno));
  }
  return pipes;
}

// Forks and executes the program; the child never returns from here.
pid_t start_child(const ProcessOptions& options, const std::string& program, const ChildPipes& pipes, bool capture) {
  std::vector<std::string> args = options.argv;
  std::vector<std::string> env = child_environment(options.environment);
  std::vector<char*> argv = c_strings(args);
  std::vector<char*> envp = c_strings(env);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) throw StageError(options.argv[0], std::string("cannot start: ") + std::strerror(errno));
  if (pid == 0) {
    // Child: only async-signal-safe calls from here on.
    if (capture) {
      ::dup2(pipes.out[1], STDOUT_FILENO);
      ::dup2(pipes.out[1], STDERR_FILENO);
    }
    ::signal(SIGINT, SIG_DFL);
    ::signal(SIGTERM, SIG_DFL);
    // No orphans: when this process dies (even by kill -9) the child gets
    // SIGTERM, which a stage handles as a clean interruption, passing it on
    // to its own children the same way. The check covers a parent that died
    // before the request took effect.
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (::getppid() != parent) ::_exit(128 + SIGTERM);
    ::execve(program.c_str(), argv.data(), envp.data());
    const int err = errno;
    [[maybe_unused]] auto n = ::write(pipes.exec[1], &err, sizeof(err));
    ::_exit(127);
  }
  return pid;
}

// The errno of a failed exec, 0 when the program started.
int exec_errno_of(ChildPipes& pipes, bool capture) {
  ::close(pipes.exec[1]);
  if (capture) ::close(pipes.out[1]);
  int exec_errno = 0;
  const bool exec_failed = ::read(pipes.exec[0], &exec_errno, sizeof(exec_errno)) == sizeof(exec_errno);
  ::close(pipes.exec[0]);
  return exec_failed ? exec_errno : 0;
}

// Passes the child's output on line by line and waits for it to end,
// asking it to stop (SIGTERM, then SIGKILL after the grace period) when the
// run is cancelled. Returns the wait status; fills the child's usage.
int wait_for_child(pid_t pid,
                   const ProcessOptions& options,
                   int out_fd,
                   LineSplitter& splitter,
                   ProcessResult& result,
                   struct rusage& usage) {
  bool term_sent = false;
  std::chrono::steady_clock::time_point term_time;
  bool pipe_open = out_fd >= 0;
  int status = 0;
  for (;;) {
    if (pipe_open) {
      pollfd pfd{out_fd, POLLIN, 0};
      const int ready = ::poll(&pfd, 1, 100);
      if (ready > 0) {
        char buffer[4096];
        const ssize_t n = ::read(out_fd, buffer, sizeof(buffer));
        if (n > 0) {
          splitter.feed(buffer, static_cast<std::size_t>(n));
        } else if (n == 0 || (errno != EINTR && errno != EAGAIN)) {
          pipe_open = false;
        }
      }
    } else {
      ::usleep(50 * 1000);
    }
    const pid_t done = ::wait4(pid, &status, WNOHANG, &usage);
    if (done == pid) return status;
    if (options.cancel_source && options.cancel_source->cancel_requested()) {
      const auto now = std::chrono::steady_clock::now();
      if (!term_sent) {
        ::kill(pid, SIGTERM);
        term_sent = true;
        term_time = now;
        result.cancelled = true;
      } else if (std::chrono::duration<double>(now - term_time).count() > options.grace_seconds) {
        ::kill(pid, SIGKILL);
      }
    }
  }
}

// Passes on what is left in the pipe after the child exited.
void drain_output(int out_fd, LineSplitter& splitter) {
  char buffer[4096];
  ::fcntl(out_fd, F_SETFL, O_NONBLOCK);
  for (ssize_t n; (n = ::read(out_fd, buffer, sizeof(buffer))) > 0;) {
    splitter.feed(buffer, static_cast<std::size_t>(n));
  }
  splitter.flush();
  ::close(out_fd);
}

void record_exit_status(int status, ProcessResult& result) {
  if (WIFEXITED(status)) {
    result.exit_code = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    result.signal = WTERMSIG(status);
    result.exit_code = 128 + result.signal;
  }
}

}  // namespace

ProcessResult run_process(const ProcessOptions& options) {
  if (options.argv.empty()) throw StageError("process", "no program given");
  const std::string program = find_executable(options.argv[0]);
  if (program.empty()) {
    throw StageError(options.argv[0], "program not found or not executable: " + options.argv[0]);
  }
  const bool capture = static_cast<bool>(options.on_line);
  ChildPipes pipes = open_pipes(options, capture);
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = start_child(options, program, pipes, capture);
  const int exec_errno = exec_errno_of(pipes, capture);

  ProcessResult result;
  LineSplitter splitter(options.on_line);
  struct rusage usage {};
  const int status = wait_for_child(pid, options, capture ? pipes.out[0] : -1, splitter, result, usage);
  if (capture) drain_output(pipes.out[0], splitter);
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.cpu_seconds = seconds_of(usage.ru_utime) + seconds_of(usage.ru_stime);
  result.peak_rss_bytes = static_cast<std::int64_t>(usage.ru_maxrss) * 1024;  // Linux: kilobytes
  if (exec_errno != 0) {
    throw StageError(options.argv[0], "cannot execute " + program + ": " + std::strerror(exec_errno));
  }
  record_exit_status(status, result);
  // A child stopped by the user's Ctrl-C (delivered to the whole process
  // group) counts as cancelled too.
  if (options.cancel_source && options.cancel_source->cancel_requested()) result.cancelled = true;
  return result;
}

}  // namespace hos
