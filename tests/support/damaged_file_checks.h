// Checks shared by the tests of every file reader: a missing or damaged file
// is an InputError that names it.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace hos::testing {

// Calls read(file) for a file in a fresh folder that does not exist, then
// once with file holding each of damaged_texts; each call must throw an
// InputError whose path() is the file. A failure names the text it read.
void expect_input_error_naming_the_file(const std::string& file_name,
                                        const std::function<void(const std::filesystem::path&)>& read,
                                        const std::vector<std::string>& damaged_texts);

}  // namespace hos::testing
