// 64-bit FNV-1a over the bytes of plain values: a cheap fingerprint that
// tells files of one run from another's (not cryptographic).
#pragma once

#include <cstddef>
#include <cstdint>

namespace hos {

class Fnv1a {
 public:
  // Adds the object representation of value (trivially copyable types only).
  template <typename T>
  void add(const T& value) {
    add_bytes(&value, sizeof(T));
  }
  void add_bytes(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      hash_ ^= bytes[i];
      hash_ *= 1099511628211ull;
    }
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 14695981039346656037ull;
};

}  // namespace hos
