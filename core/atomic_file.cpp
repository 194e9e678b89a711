#include "core/atomic_file.h"

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

}  // namespace

void write_atomically(const fs::path& target, const std::function<void(const fs::path&)>& write) {
  const fs::path parent = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  if (!fs::is_directory(parent)) throw OutputError(target.string(), "folder " + parent.string() + " does not exist");
  const fs::path tmp = temporary_sibling(target);
  try {
    write(tmp);
    std::error_code ec;
    fs::rename(tmp, target, ec);
    if (ec) throw OutputError(target.string(), ec.message());
  } catch (...) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
}

void write_folder_atomically(const fs::path& target_dir,
                             const std::function<void(const fs::path&)>& write) {
  const fs::path parent = target_dir.parent_path().empty() ? fs::path(".") : target_dir.parent_path();
  if (!fs::is_directory(parent)) throw OutputError(target_dir.string(), "folder " + parent.string() + " does not exist");
  const fs::path tmp = temporary_sibling(target_dir);
  try {
    fs::create_directories(tmp);
    write(tmp);
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

}  // namespace hos
