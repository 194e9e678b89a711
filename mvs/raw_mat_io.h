// A matrix's pixels as raw bytes in a binary stream, as the .dmap files and
// fusion's spill files keep them: what is read back is what was written,
// bit for bit. The size and type are the caller's to record.
#pragma once

#include <istream>
#include <opencv2/core.hpp>
#include <ostream>

namespace hos::mvs {

// Writes m's pixels, row after row; check the stream afterwards.
inline void write_raw_mat(std::ostream& out, const cv::Mat& m) {
  const cv::Mat c = m.isContinuous() ? m : m.clone();
  out.write(reinterpret_cast<const char*>(c.data), static_cast<std::streamsize>(c.total() * c.elemSize()));
}

// Fills m (allocated, continuous, of the written size and type) from the
// stream; check the stream afterwards.
inline void read_raw_mat(std::istream& in, cv::Mat& m) {
  in.read(reinterpret_cast<char*>(m.data), static_cast<std::streamsize>(m.total() * m.elemSize()));
}

}  // namespace hos::mvs
