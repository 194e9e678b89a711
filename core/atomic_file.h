// Writing outputs so that a crash never leaves a file that looks finished.
#pragma once

#include <filesystem>
#include <functional>

namespace hos {

// Calls write(tmp) with a temporary path next to target, then renames tmp to
// target. On any exception the temporary is removed and the exception rethrown.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path& tmp)>& write);

// The same for a folder: write fills tmp_dir, which then replaces target_dir.
void write_folder_atomically(const std::filesystem::path& target_dir,
                             const std::function<void(const std::filesystem::path& tmp_dir)>& write);

}  // namespace hos
