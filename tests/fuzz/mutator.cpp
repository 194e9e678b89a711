#include "tests/fuzz/mutator.h"

#include <array>
#include <cstdlib>
#include <fstream>
#include <iterator>

namespace hos::testing {
namespace {

// Bytes and numbers that break careless parsers: sign bits, maxima, zero,
// NaN and infinities, counts beyond memory, exponents beyond double.
constexpr std::array<unsigned char, 8> kSpecialBytes{0x00, 0xff, 0x7f, 0x80, 0x01, 0xfe, '\n', ' '};
constexpr std::array<const char*, 14> kSpecialNumbers{"0",
                                                      "-1",
                                                      "nan",
                                                      "inf",
                                                      "-inf",
                                                      "1e308",
                                                      "-1e308",
                                                      "1e-320",
                                                      "4294967295",
                                                      "-2147483648",
                                                      "18446744073709551615",
                                                      "9999999999999",
                                                      "0.0000001",
                                                      "-0"};

bool is_number_char(char c) { return (c >= '0' && c <= '9') || c == '.' || c == '-' || c == 'e' || c == '+'; }

}  // namespace

std::string Mutator::mutate(const std::string& input, bool text) {
  std::string s = input;
  const std::size_t count = 1 + below(4);
  for (std::size_t m = 0; m < count; ++m) {
    switch (below(text ? 8 : 6)) {
      case 0:
        flip_bits(s);
        break;
      case 1:
        set_special_bytes(s);
        break;
      case 2:
        erase_run(s);
        break;
      case 3:
        repeat_run(s);
        break;
      case 4:
        truncate(s);
        break;
      case 5:
        set_special_bytes(s);
        break;
      case 6:
        replace_number(s);
        break;
      default:
        swap_lines(s);
        break;
    }
  }
  return s;
}

void Mutator::flip_bits(std::string& s) {
  if (s.empty()) return;
  for (std::size_t k = 0, n = 1 + below(8); k < n; ++k) s[below(s.size())] ^= static_cast<char>(1u << below(8));
}

void Mutator::set_special_bytes(std::string& s) {
  if (s.empty()) return;
  const std::size_t at = below(s.size());
  const std::size_t n = std::min<std::size_t>(1 + below(8), s.size() - at);
  const char value = static_cast<char>(kSpecialBytes[below(kSpecialBytes.size())]);
  for (std::size_t k = 0; k < n; ++k) s[at + k] = value;
}

void Mutator::erase_run(std::string& s) {
  if (s.empty()) return;
  const std::size_t at = below(s.size());
  s.erase(at, 1 + below(std::min<std::size_t>(64, s.size() - at)));
}

void Mutator::repeat_run(std::string& s) {
  if (s.empty() || s.size() > (1u << 22)) return;
  const std::size_t at = below(s.size());
  const std::string run = s.substr(at, 1 + below(64));
  s.insert(below(s.size() + 1), run);
}

void Mutator::truncate(std::string& s) { s.resize(below(s.size() + 1)); }

void Mutator::replace_number(std::string& s) {
  // The start of a run of number characters, found from a random place.
  std::size_t at = below(s.size() + 1);
  while (at < s.size() && !is_number_char(s[at])) ++at;
  if (at >= s.size()) return;
  std::size_t end = at;
  while (end < s.size() && is_number_char(s[end])) ++end;
  s.replace(at, end - at, kSpecialNumbers[below(kSpecialNumbers.size())]);
}

void Mutator::swap_lines(std::string& s) {
  const std::size_t a = s.find('\n', below(s.size() + 1));
  if (a == std::string::npos) return;
  const std::size_t b = s.find('\n', a + 1);
  if (b == std::string::npos) return;
  const std::size_t c = s.find('\n', b + 1);
  if (c == std::string::npos) return;
  // Lines (a, b] and (b, c] change places.
  const std::string first = s.substr(a + 1, b - a), second = s.substr(b + 1, c - b);
  s.replace(a + 1, c - a, second + first);
}

int fuzz_iterations(int fallback) {
  const char* env = std::getenv("HOS_FUZZ_ITERATIONS");
  return env && *env ? std::max(1, std::atoi(env)) : fallback;
}

std::uint64_t fuzz_seed() {
  const char* env = std::getenv("HOS_FUZZ_SEED");
  return env && *env ? std::strtoull(env, nullptr, 10) : 1;
}

void write_file(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace hos::testing
