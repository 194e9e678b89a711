// Which disk a folder is on and how much room is left there, for messages
// about full disks and for warnings before a stage runs out of room.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace hos {

struct DiskSpace {
  std::filesystem::path mount_point;  // the top folder of the disk holding the folder
  std::uintmax_t free_bytes = 0;      // available to this user
  bool known = false;                 // false when the folder cannot be queried
};

// The disk holding folder (or its nearest existing parent).
DiskSpace disk_space(const std::filesystem::path& folder);

// "the disk mounted at /data (1234 MB free)", for error messages.
std::string describe_disk(const std::filesystem::path& folder);

// Whether a line of a tool's output says the disk is full (SQLite's
// "database or disk is full", the C library's "No space left on device").
bool says_disk_full(const std::string& line);

}  // namespace hos
