#include "pipeline/file_hash.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <vector>

namespace hos::pipeline {
namespace fs = std::filesystem;
namespace {

std::vector<fs::path> sorted_files(const fs::path& folder, const std::vector<fs::path>& excluded = {}) {
  std::vector<fs::path> files;
  std::error_code ec, base_ec;
  const fs::path base = excluded.empty() ? folder : fs::weakly_canonical(folder, base_ec);
  for (auto it = fs::recursive_directory_iterator(folder, fs::directory_options::skip_permission_denied, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    // An entry that cannot be examined (a symlink loop) is left out; its own
    // error must not end the listing.
    std::error_code entry_ec;
    if (!excluded.empty()) {
      const fs::path here = (base / it->path().lexically_relative(folder)).lexically_normal();
      if (std::find(excluded.begin(), excluded.end(), here) != excluded.end()) {
        if (it->is_directory(entry_ec)) it.disable_recursion_pending();
        continue;
      }
    }
    if (it->is_regular_file(entry_ec)) files.push_back(it->path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

void Fingerprint::add(const void* data, std::size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    state_ ^= bytes[i];
    state_ *= 1099511628211ull;
  }
}

void Fingerprint::add(std::string_view bytes) {
  add(bytes.data(), bytes.size());
  add("\0", 1);  // separator: "ab"+"c" differs from "a"+"bc"
}

void Fingerprint::add_file_contents(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    add("<missing>" + file.string());
    return;
  }
  std::vector<char> buffer(1 << 16);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    add(buffer.data(), static_cast<std::size_t>(in.gcount()));
  }
  add("<end>");
}

void Fingerprint::add_folder_listing(const fs::path& folder, const std::vector<fs::path>& excluded) {
  add_file_listing(folder, sorted_files(folder, excluded));
}

void Fingerprint::add_file_listing(const fs::path& folder, const std::vector<fs::path>& files) {
  add("<listing>");
  for (const auto& file : files) {
    std::error_code ec;
    const auto size = fs::file_size(file, ec);
    const auto time = fs::last_write_time(file, ec).time_since_epoch().count();
    add(fs::relative(file, folder).string() + " " + std::to_string(size) + " " + std::to_string(time));
  }
}

void Fingerprint::add_folder_contents(const fs::path& folder) {
  add("<contents>");
  for (const auto& file : sorted_files(folder)) {
    add(fs::relative(file, folder).string());
    add_file_contents(file);
  }
}

std::string Fingerprint::hex() const {
  char text[17];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(state_));
  return text;
}

}  // namespace hos::pipeline
