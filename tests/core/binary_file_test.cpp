// core/binary_file.*: the tag and version every versioned binary file starts with.
#include "core/binary_file.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <string>

#include "core/binary_values.h"
#include "core/error.h"
#include "tests/support/test_support.h"

namespace hos {
namespace {

constexpr BinaryFileKind kKind{{'H', 'O', 'S', 'T', 'E', 'S', 'T', 'F'}, 3, "hos-test", "test data", "write it again"};

// The InputError's message of reading the start of file as kKind, or "" when it reads.
std::string read_error(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  try {
    read_binary_file_start(in, file, kKind);
  } catch (const InputError& e) {
    return e.reason();
  }
  return "";
}

void write_bytes(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream(file, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

TEST(BinaryFile, WritesTagVersionAndBodyAndReadsThemBack) {
  hos::testing::TempDir dir;
  const std::filesystem::path file = dir / "sub" / "a.bin";
  write_binary_file(file, kKind, [](std::ofstream& out) { write_value(out, std::int32_t{-7}); });
  ASSERT_EQ(std::filesystem::file_size(file), 8u + 4u + 4u);
  std::ifstream in(file, std::ios::binary);
  read_binary_file_start(in, file, kKind);
  std::int32_t body = 0;
  ASSERT_TRUE(read_value(in, body));
  EXPECT_EQ(body, -7);
  // The tag in the file's first bytes, the version after it.
  std::ifstream raw(file, std::ios::binary);
  std::string tag(8, '\0');
  raw.read(tag.data(), 8);
  EXPECT_EQ(tag, "HOSTESTF");
  std::uint32_t version = 0;
  ASSERT_TRUE(read_value(raw, version));
  EXPECT_EQ(version, 3u);
}

TEST(BinaryFile, AFailedWriteIsAnOutputErrorNamingTheFileAndTheKind) {
  hos::testing::TempDir dir;
  const std::filesystem::path file = dir / "a.bin";
  try {
    write_binary_file(file, kKind, [](std::ofstream& out) { out.setstate(std::ios::badbit); });
    FAIL() << "a failed write was not reported";
  } catch (const OutputError& e) {
    EXPECT_EQ(std::string(e.what()), file.string() + ": cannot write: the test data");
  }
  EXPECT_FALSE(std::filesystem::exists(file)) << "nothing half-written is left under the file's name";
}

TEST(BinaryFile, RefusesOtherKindsVersionsAndTruncatedStarts) {
  hos::testing::TempDir dir;
  write_bytes(dir / "other", std::string("HOSTVIEW\3\0\0\0", 12));
  EXPECT_EQ(read_error(dir / "other"), "not a hos-test test data file");
  write_bytes(dir / "short", "HOST");
  EXPECT_EQ(read_error(dir / "short"), "not a hos-test test data file");
  write_bytes(dir / "no-version", std::string("HOSTESTF\3\0", 10));
  EXPECT_EQ(read_error(dir / "no-version"), "truncated test data (the header is incomplete)");
  write_binary_file(dir / "v3", kKind, [](std::ofstream&) {});
  EXPECT_EQ(read_error(dir / "v3"), "");
  BinaryFileKind newer = kKind;
  newer.version = 4;
  std::ifstream in(dir / "v3", std::ios::binary);
  try {
    read_binary_file_start(in, dir / "v3", newer);
    ADD_FAILURE() << "read a version 3 file as version 4";
  } catch (const InputError& e) {
    EXPECT_EQ(e.reason(), "test data of format version 3, this hos reads version 4; write it again");
  }
}

}  // namespace
}  // namespace hos
