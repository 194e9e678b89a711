// Seeded mutations of valid files, for fuzzing the readers: bit flips,
// special bytes, removed, repeated and inserted runs, truncation, and (for
// text formats) numbers replaced by extreme ones. The same seed gives the
// same mutants, so a failure is reproduced by its seed and iteration.
#pragma once

#include <cstdint>
#include <filesystem>
#include <random>
#include <string>

namespace hos::testing {

class Mutator {
 public:
  explicit Mutator(std::uint64_t seed) : rng_(seed) {}
  // A mutant of input: one to four mutations of random kinds; text-aware
  // ones (numbers, words) only when text is true.
  std::string mutate(const std::string& input, bool text);

 private:
  std::size_t below(std::size_t n) { return n == 0 ? 0 : std::uniform_int_distribution<std::size_t>(0, n - 1)(rng_); }
  void flip_bits(std::string& s);
  void set_special_bytes(std::string& s);
  void erase_run(std::string& s);
  void repeat_run(std::string& s);
  void truncate(std::string& s);
  void replace_number(std::string& s);
  void swap_lines(std::string& s);

  std::mt19937_64 rng_;
};

// How many mutants each fuzz test tries (HOS_FUZZ_ITERATIONS, default
// `fallback`) and the base seed (HOS_FUZZ_SEED, default 1).
int fuzz_iterations(int fallback);
std::uint64_t fuzz_seed();

// Writes bytes to path (binary).
void write_file(const std::filesystem::path& path, const std::string& bytes);
// Reads a whole file as bytes ("" if it cannot be read).
std::string read_file(const std::filesystem::path& path);

}  // namespace hos::testing
