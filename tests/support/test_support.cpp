#include "tests/support/test_support.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>

namespace hos::testing {
namespace fs = std::filesystem;

TempDir::TempDir(const std::string& prefix) {
  std::random_device device;
  for (int attempt = 0; attempt < 100; ++attempt) {
    fs::path candidate = fs::temp_directory_path() /
                         (prefix + "-" + std::to_string(getpid()) + "-" + std::to_string(device() % 1000000u));
    if (fs::create_directories(candidate)) {
      path_ = candidate;
      return;
    }
  }
  throw std::runtime_error("cannot create a temporary folder");
}

TempDir::~TempDir() {
  if (std::getenv("HOS_KEEP_TEST_DIRS")) return;
  std::error_code ignored;
  fs::remove_all(path_, ignored);
}

fs::path bin_dir() {
  const char* dir = std::getenv("HOS_BIN_DIR");
  return dir ? fs::path(dir) : fs::current_path() / "bin";
}

fs::path executable(const std::string& name) { return bin_dir() / name; }

std::string missing_executables(const std::vector<std::string>& names) {
  std::string missing;
  for (const auto& name : names) {
    if (!fs::exists(executable(name))) missing += " " + name;
  }
  return missing;
}

fs::path source_dir() {
  const char* dir = std::getenv("HOS_SOURCE_DIR");
  return dir ? fs::path(dir) : fs::current_path();
}

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') {
      out += "'\\''";
    } else {
      out += c;
    }
  }
  return out + "'";
}

int run_command(const std::string& command, const fs::path& log_path) {
  std::string full = command;
  if (!log_path.empty()) full += " > " + shell_quote(log_path.string()) + " 2>&1";
  const int status = std::system(full.c_str());
  if (status == -1) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

int count_occurrences(const std::string& text, const std::string& part) {
  int n = 0;
  for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

std::vector<int> jpeg_sampling_factors(const std::string& jpeg) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(jpeg[i]); };
  for (std::size_t i = 2; i + 9 < jpeg.size(); ++i) {
    if (byte(i) != 0xFF || byte(i + 1) != 0xC0) continue;
    std::vector<int> factors;
    for (std::size_t c = 0; c < byte(i + 9) && i + 11 + 3 * c < jpeg.size(); ++c)
      factors.push_back(byte(i + 11 + 3 * c));
    return factors;
  }
  return {};
}

int make_synth_scene(const fs::path& folder, int views, int holdout, const fs::path& log_path, SynthPhotoSize size) {
  return run_command(shell_quote(executable("hos-synth").string()) + " --output " + shell_quote(folder.string()) +
                         " --views " + std::to_string(views) + " --width " + std::to_string(size.width) + " --height " +
                         std::to_string(size.height) + " --seed 1 --holdout " + std::to_string(holdout),
                     log_path);
}

}  // namespace hos::testing
