// Raw values in the project's binary files (depth maps, view data, tile
// functions): written and read in the machine's byte order, so a file read
// back is the file written, bit for bit.
#pragma once

#include <fstream>

namespace hos {

template <typename T>
void write_value(std::ofstream& out, const T& value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof(T));
}

// False when the stream ends before the value.
template <typename T>
bool read_value(std::ifstream& in, T& value) {
  return static_cast<bool>(in.read(reinterpret_cast<char*>(&value), sizeof(T)));
}

}  // namespace hos
