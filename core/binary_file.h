// The start every versioned binary file of the project has (tile functions,
// texture view data): an 8-character tag naming the kind of file, then a
// uint32 format version; the kind's own header and data follow (written with
// binary_values.h).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string_view>

namespace hos {

struct BinaryFileKind {
  std::array<char, 8> tag;
  std::uint32_t version = 0;
  std::string_view program;  // the one that writes it, for messages ("hos-recon")
  std::string_view name;     // what it holds ("tile function")
  std::string_view redo;     // how to make it again after a version change ("solve the tile again")
};

// Writes file atomically, creating its folder: the tag, the version, then
// what body writes. Throws OutputError ("FILE: cannot write: the <name>") when a
// write fails.
void write_binary_file(const std::filesystem::path& file,
                       const BinaryFileKind& kind,
                       const std::function<void(std::ofstream& out)>& body);

// Reads the tag and version from the start of in (file names it). Throws
// InputError naming the file when it is not of this kind ("not a <program>
// <name> file"), ends before the version, or is of another format version.
void read_binary_file_start(std::ifstream& in, const std::filesystem::path& file, const BinaryFileKind& kind);

}  // namespace hos
