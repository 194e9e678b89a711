#include "core/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ios>
#include <random>
#include <system_error>

#include "core/error.h"

namespace hos {
namespace fs = std::filesystem;
namespace {

fs::path temporary_sibling(const fs::path& target) {
  std::random_device device;
  const auto tag = std::to_string(device() % 1000000u);
  return target.parent_path() / (".tmp-" + tag + "-" + target.filename().string());
}

fs::path folder_of(const fs::path& target) {
  return target.parent_path().empty() ? fs::path(".") : target.parent_path();
}

// Runs write(tmp); what the filesystem or a stream reports becomes an
// OutputError for target, so no write failure is an internal error.
void write_reporting_failures(const fs::path& target,
                              const fs::path& tmp,
                              const std::function<void(const fs::path&)>& write) {
  try {
    write(tmp);
  } catch (const fs::filesystem_error& e) {
    throw OutputError(target.string(), e.code().message());
  } catch (const std::ios_base::failure& e) {
    throw OutputError(target.string(), e.what());
  }
}

}  // namespace

void write_atomically(const fs::path& target, const std::function<void(const fs::path&)>& write) {
  const fs::path parent = folder_of(target);
  if (!fs::is_directory(parent)) throw OutputError(target.string(), "folder " + parent.string() + " does not exist");
  const fs::path tmp = temporary_sibling(target);
  try {
    write_reporting_failures(target, tmp, write);
    std::error_code ec;
    fs::rename(tmp, target, ec);
    if (ec) throw OutputError(target.string(), ec.message());
  } catch (...) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
}

void write_folder_atomically(const fs::path& target_dir, const std::function<void(const fs::path&)>& write) {
  const fs::path parent = folder_of(target_dir);
  if (!fs::is_directory(parent))
    throw OutputError(target_dir.string(), "folder " + parent.string() + " does not exist");
  const fs::path tmp = temporary_sibling(target_dir);
  try {
    write_reporting_failures(target_dir, tmp, [&](const fs::path& dir) {
      fs::create_directories(dir);
      write(dir);
    });
    std::error_code ec;
    fs::remove_all(target_dir, ec);
    fs::rename(tmp, target_dir, ec);
    if (ec) throw OutputError(target_dir.string(), ec.message());
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(tmp, ignored);
    throw;
  }
}

void check_writable_target(const fs::path& target) {
  std::error_code ec;
  if (fs::is_directory(target, ec)) throw OutputError(target.string(), "is a folder");
  const fs::path folder = folder_of(target);
  if (!fs::is_directory(folder, ec))
    throw OutputError(target.string(), "its folder " + folder.string() + " does not exist");
  const fs::path probe = temporary_sibling(target);
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) {
    throw OutputError(target.string(), "cannot create a file in " + folder.string() + ": " + std::strerror(errno));
  }
  ::close(fd);
  fs::remove(probe, ec);
}

}  // namespace hos
