// Helpers shared by the test binaries.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/error.h"

namespace hos::testing {

// The message of the InputError that read() throws, or "" when it reads
// without one (a bad-input test checks the message names the file and
// reason).
template <class Read>
std::string input_error_of(Read&& read) {
  try {
    read();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

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
// A built executable: bin_dir() / name.
std::filesystem::path executable(const std::string& name);
// The names of the executables that are not built, each after a space
// ("" when all are), for GTEST_SKIP messages.
std::string missing_executables(const std::vector<std::string>& names);
// Root of the source tree (HOS_SOURCE_DIR, set by ctest).
std::filesystem::path source_dir();
// Runs a shell command; returns its exit status (not the raw wait status).
// Output goes to log_path if given.
int run_command(const std::string& command, const std::filesystem::path& log_path = {});
// Quotes a string for /bin/sh.
std::string shell_quote(const std::string& s);
// The whole content of a text file ("" if it cannot be read).
std::string read_text(const std::filesystem::path& file);
// Whether text holds part, and how often (overlapping matches count).
bool contains(const std::string& text, const std::string& part);
int count_occurrences(const std::string& text, const std::string& part);
// The sampling byte (horizontal << 4 | vertical) of each component in a
// JPEG's baseline frame header: {0x11, 0x11, 0x11} for 4:4:4, {0x22, 0x11,
// 0x11} for 4:2:0; empty without one.
std::vector<int> jpeg_sampling_factors(const std::string& jpeg_bytes);
// Photo size of a rendered synthetic scene.
struct SynthPhotoSize {
  int width = 640;
  int height = 480;
};
// Renders the default hos-synth scene (seed 1) into folder with `views` views
// plus `holdout` held-out ones; returns hos-synth's exit status (its output
// goes to log_path).
int make_synth_scene(const std::filesystem::path& folder,
                     int views,
                     int holdout,
                     const std::filesystem::path& log_path,
                     SynthPhotoSize size = {});

}  // namespace hos::testing
