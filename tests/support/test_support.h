// Helpers shared by the test binaries.
#pragma once

#include <filesystem>
#include <string>

namespace hos::testing {

// A fresh empty folder under the system temp dir, removed by the destructor
// (kept when HOS_KEEP_TEST_DIRS is set, for debugging).
class TempDir {
 public:
  explicit TempDir(const std::string& prefix = "hos-test");
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

// Folder of the built executables (HOS_BIN_DIR, set by ctest).
std::filesystem::path bin_dir();
// Root of the source tree (HOS_SOURCE_DIR, set by ctest).
std::filesystem::path source_dir();
// Runs a shell command; returns its exit status (not the raw wait status).
// Output goes to log_path if given.
int run_command(const std::string& command, const std::filesystem::path& log_path = {});
// Quotes a string for /bin/sh.
std::string shell_quote(const std::string& s);

}  // namespace hos::testing
