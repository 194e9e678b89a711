#include "core/binary_file.h"

#include "core/atomic_file.h"
#include "core/binary_values.h"
#include "core/error.h"
#include "core/reporter.h"

namespace hos {

void write_binary_file(const std::filesystem::path& file,
                       const BinaryFileKind& kind,
                       const std::function<void(std::ofstream& out)>& body) {
  if (!file.parent_path().empty()) std::filesystem::create_directories(file.parent_path());
  write_atomically(file, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out.write(kind.tag.data(), static_cast<std::streamsize>(kind.tag.size()));
    write_value(out, kind.version);
    body(out);
    if (!out) throw OutputError(file.string(), format_message("the ", kind.name));
  });
}

void read_binary_file_start(std::ifstream& in, const std::filesystem::path& file, const BinaryFileKind& kind) {
  std::array<char, 8> tag{};
  in.read(tag.data(), static_cast<std::streamsize>(tag.size()));
  if (!in || tag != kind.tag)
    throw InputError(file.string(), format_message("not a ", kind.program, " ", kind.name, " file"));
  std::uint32_t version = 0;
  if (!read_value(in, version)) {
    throw InputError(file.string(), format_message("truncated ", kind.name, " (the header is incomplete)"));
  }
  if (version != kind.version) {
    throw InputError(file.string(), format_message(kind.name, " of format version ", version,
                                                   ", this hos reads version ", kind.version, "; ", kind.redo));
  }
}

}  // namespace hos
