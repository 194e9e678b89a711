// Running an external program (COLMAP, a stage executable) as a child
// process: output captured line by line or passed through, cooperative
// cancellation, exit status, wall and CPU time and peak memory of the child.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hos {

class Reporter;

struct ProcessOptions {
  std::vector<std::string> argv;  // argv[0] is looked up on PATH if it has no '/'
  // Variables set (or replaced) in the child's environment.
  std::vector<std::pair<std::string, std::string>> environment;
  // When set, the child's stdout and stderr are merged and delivered here one
  // line at a time ('\n' or '\r' ends a line). When empty, the child writes
  // to this process's stdout/stderr directly (progress bars keep working).
  std::function<void(std::string_view line)> on_line;
  // Polled while the child runs; once it reports cancellation the child gets
  // SIGTERM (SIGKILL after grace_seconds) and the result says cancelled.
  const Reporter* cancel_source = nullptr;
  double grace_seconds = 10.0;
};

struct ProcessResult {
  int exit_code = -1;      // exit status, or 128 + signal number
  int signal = 0;          // signal that ended the child, 0 if it exited
  bool cancelled = false;  // we stopped it because cancellation was requested
  double wall_seconds = 0.0;
  // User plus system CPU time of the child and the processes it waited for
  // (wait4's rusage): on a shared machine the figure that does not depend
  // on the load.
  double cpu_seconds = 0.0;
  std::int64_t peak_rss_bytes = 0;  // of the child and the processes it waited for
  bool ok() const { return exit_code == 0 && !cancelled; }
};

// Starts the program and waits for it. The child is sent SIGTERM when the
// calling thread ends (PR_SET_PDEATHSIG: also when this process is killed),
// so it never outlives its caller; call it from a thread that waits for it. Throws StageError when
// the program cannot be started at all (not found, not executable), naming it.
ProcessResult run_process(const ProcessOptions& options);

// Full path of program found on PATH (or program itself if it contains a
// '/' and is executable); empty if not found.
std::string find_executable(const std::string& program);

}  // namespace hos
