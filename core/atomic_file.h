// Writing outputs so that a crash never leaves a file that looks finished.
#pragma once

#include <filesystem>
#include <functional>

namespace hos {

// Calls write(tmp) with a temporary path next to target, then renames tmp to
// target. On any exception the temporary is removed and the exception
// rethrown; a filesystem or stream failure inside write (a full disk, a
// read-only folder) becomes an OutputError naming target and the reason.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path& tmp)>& write);

// The same for a folder: write fills tmp_dir, which then replaces target_dir.
void write_folder_atomically(const std::filesystem::path& target_dir,
                             const std::function<void(const std::filesystem::path& tmp_dir)>& write);

// Checks, before any work, that target can be written: it is not a folder,
// its folder exists, and a file can be created there (a probe file, removed
// at once). Throws OutputError naming target and the reason.
void check_writable_target(const std::filesystem::path& target);

}  // namespace hos
