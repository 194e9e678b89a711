// Fingerprints of a stage's inputs, so a re-run can tell whether they changed.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace hos::pipeline {

// 64-bit FNV-1a: not cryptographic, only to detect changed inputs.
class Fingerprint {
 public:
  void add(std::string_view bytes);
  void add(const void* data, std::size_t size);
  // The contents of a file (a missing file adds a marker, not an error).
  void add_file_contents(const std::filesystem::path& file);
  // Names, sizes and modification times of the files of a folder (recursively,
  // sorted), not their contents: cheap for folders of large photos. Files
  // and folders in `excluded` (absolute, normalised) are left out.
  void add_folder_listing(const std::filesystem::path& folder, const std::vector<std::filesystem::path>& excluded = {});
  // Names (relative to folder), sizes and modification times of the given
  // files, in their order.
  void add_file_listing(const std::filesystem::path& folder, const std::vector<std::filesystem::path>& files);
  // Contents of every file of a folder (recursively, sorted by path).
  void add_folder_contents(const std::filesystem::path& folder);
  std::string hex() const;

 private:
  std::uint64_t state_ = 1469598103934665603ull;
};

}  // namespace hos::pipeline
