#include "pipeline/workspace_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "core/error.h"

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

// What the owner wrote: "pid <n>", or "" for a lock released cleanly.
std::string read_owner(int fd) {
  char text[64] = {};
  const ssize_t n = ::pread(fd, text, sizeof(text) - 1, 0);
  std::string owner(text, n > 0 ? static_cast<std::size_t>(n) : 0);
  while (!owner.empty() && (owner.back() == '\n' || owner.back() == ' ')) owner.pop_back();
  return owner;
}

void write_owner(int fd, const std::string& owner) {
  [[maybe_unused]] const int t = ::ftruncate(fd, 0);
  [[maybe_unused]] const ssize_t n = ::pwrite(fd, owner.data(), owner.size(), 0);
}

}  // namespace

fs::path WorkspaceLock::file_in(const fs::path& workspace) { return workspace / ".lock"; }

WorkspaceLock::WorkspaceLock(const fs::path& workspace, Reporter& reporter) {
  const fs::path file = file_in(workspace);
  // Close-on-exec: a stage child must not keep the lock after the driver dies.
  fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0)
    throw OutputError(file.string(), std::string("cannot create the workspace lock: ") + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    const std::string owner = read_owner(fd_);
    ::close(fd_);
    fd_ = -1;
    if (err != EWOULDBLOCK) {
      throw OutputError(file.string(), std::string("cannot lock the workspace: ") + std::strerror(err));
    }
    throw ConfigError("workspace " + workspace.string(), "is in use by another hos-pipeline (" +
                                                             (owner.empty() ? std::string("pid unknown") : owner) +
                                                             "); wait for it to finish, or give another --workspace");
  }
  const std::string previous = read_owner(fd_);
  if (!previous.empty()) {
    reporter.warn("taking over the workspace lock of an earlier run that did not finish (" + previous +
                  "); its finished stages are kept");
  }
  write_owner(fd_, "pid " + std::to_string(::getpid()));
}

WorkspaceLock::~WorkspaceLock() {
  if (fd_ < 0) return;
  write_owner(fd_, "");  // released cleanly: the next run has nothing to take over
  ::close(fd_);
}

}  // namespace hos::pipeline
