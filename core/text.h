// Small text helpers: ASCII lower-casing, for file extensions and names
// compared without case.
#pragma once

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

namespace hos {

inline std::string lower_case(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// The extension of path with its dot, lower-cased: ".jpg" for "A.JPG".
inline std::string lower_case_extension(const std::filesystem::path& path) {
  return lower_case(path.extension().string());
}

}  // namespace hos
