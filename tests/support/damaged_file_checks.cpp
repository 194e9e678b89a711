#include "tests/support/damaged_file_checks.h"

#include <gtest/gtest.h>

#include <fstream>

#include "core/error.h"
#include "tests/support/test_support.h"

namespace hos::testing {
namespace {

// One read of file, described by why in a failure.
void expect_one_input_error(const std::filesystem::path& file,
                            const std::function<void(const std::filesystem::path&)>& read,
                            const std::string& why) {
  try {
    read(file);
    ADD_FAILURE() << why << ": no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), file.string()) << why;
  }
}

}  // namespace

void expect_input_error_naming_the_file(const std::string& file_name,
                                        const std::function<void(const std::filesystem::path&)>& read,
                                        const std::vector<std::string>& damaged_texts) {
  const TempDir dir;
  const std::filesystem::path file = dir / file_name;
  expect_one_input_error(file, read, "missing");
  for (const std::string& text : damaged_texts) {
    std::ofstream(file) << text;
    expect_one_input_error(file, read, "holding '" + text + "'");
  }
}

}  // namespace hos::testing
