// What a file holds, told by its first bytes, never by its name: a photo
// saved with the wrong extension (an iPhone HEIC named .jpg, a PNG named
// .jpg) is read as what it is.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

namespace hos::sfm {

enum class PhotoFormat { kUnknown, kJpeg, kPng, kTiff, kBmp, kHeif };

// How many leading bytes photo_format_of needs at most.
inline constexpr std::size_t kPhotoFormatHeadBytes = 64;

// The format of data whose first size bytes are given (fewer than
// kPhotoFormatHeadBytes is fine: a short file).
PhotoFormat photo_format_of(const std::uint8_t* head, std::size_t size);

// The format of a file by its first bytes; kUnknown when it cannot be read.
PhotoFormat photo_format_of_file(const std::filesystem::path& file);

// "JPEG", "PNG", "TIFF", "BMP", "HEIF", "unknown".
std::string photo_format_name(PhotoFormat format);

}  // namespace hos::sfm
