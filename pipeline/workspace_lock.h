// One hos-pipeline per workspace: a second run on the same workspace would
// rebuild files under the first one's feet. The lock is an flock(2) on
// WS/.lock holding the owner's pid; the kernel drops it when its owner dies,
// so a lock left by a killed run is taken over (with a warning) instead of
// blocking the workspace forever.
#pragma once

#include <filesystem>

#include "core/reporter.h"

namespace hos::pipeline {

class WorkspaceLock {
 public:
  // Locks workspace (an existing folder). Throws ConfigError naming the
  // running process when another hos-pipeline holds it, OutputError when the
  // lock file cannot be created. Warns when it takes over a killed run's lock.
  WorkspaceLock(const std::filesystem::path& workspace, Reporter& reporter);
  ~WorkspaceLock();
  WorkspaceLock(const WorkspaceLock&) = delete;
  WorkspaceLock& operator=(const WorkspaceLock&) = delete;

  // The lock file inside a workspace.
  static std::filesystem::path file_in(const std::filesystem::path& workspace);

 private:
  int fd_ = -1;
};

}  // namespace hos::pipeline
