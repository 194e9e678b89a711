#include "core/disk_space.h"

#include <sys/stat.h>

#include <cmath>
#include <system_error>

namespace hos {
namespace fs = std::filesystem;
namespace {

fs::path nearest_existing(fs::path folder) {
  std::error_code ec;
  folder = fs::absolute(folder, ec);
  while (!folder.empty() && !fs::exists(folder, ec) && folder.has_parent_path() && folder != folder.parent_path()) {
    folder = folder.parent_path();
  }
  return folder;
}

// The highest parent on the same device: where the disk is mounted.
fs::path mount_point_of(const fs::path& existing) {
  struct stat here {};
  if (::stat(existing.c_str(), &here) != 0) return existing;
  fs::path top = existing;
  while (top.has_parent_path() && top != top.parent_path()) {
    struct stat up {};
    if (::stat(top.parent_path().c_str(), &up) != 0 || up.st_dev != here.st_dev) break;
    top = top.parent_path();
  }
  return top;
}

}  // namespace

DiskSpace disk_space(const fs::path& folder) {
  DiskSpace out;
  const fs::path existing = nearest_existing(folder);
  std::error_code ec;
  const fs::space_info info = fs::space(existing, ec);
  out.mount_point = mount_point_of(existing);
  if (!ec) {
    out.free_bytes = info.available;
    out.known = true;
  }
  return out;
}

std::string describe_disk(const fs::path& folder) {
  const DiskSpace d = disk_space(folder);
  std::string text = "the disk mounted at " + d.mount_point.string();
  if (d.known) {
    text += " (" + std::to_string(std::llround(static_cast<double>(d.free_bytes) / (1024.0 * 1024.0))) + " MB free)";
  }
  return text;
}

bool says_disk_full(const std::string& line) {
  return line.find("database or disk is full") != std::string::npos ||
         line.find("No space left on device") != std::string::npos;
}

}  // namespace hos
