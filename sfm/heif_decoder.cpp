#include "sfm/heif_decoder.h"

#include <libheif/heif.h>

#include <memory>
#include <opencv2/imgproc.hpp>

namespace hos::sfm {
namespace {

struct ContextFree {
  void operator()(heif_context* c) const { heif_context_free(c); }
};
struct HandleRelease {
  void operator()(heif_image_handle* h) const { heif_image_handle_release(h); }
};
struct ImageRelease {
  void operator()(heif_image* i) const { heif_image_release(i); }
};

// The handle's first Exif item: a 4-byte big-endian offset, then (after
// that many bytes) the TIFF structure.
ExifBlock exif_of(const heif_image_handle* handle) {
  heif_item_id id = 0;
  if (heif_image_handle_get_list_of_metadata_block_IDs(handle, "Exif", &id, 1) < 1) return {};
  std::vector<std::uint8_t> item(heif_image_handle_get_metadata_size(handle, id));
  if (item.size() < 4 || heif_image_handle_get_metadata(handle, id, item.data()).code != heif_error_Ok) return {};
  const std::size_t offset =
      std::size_t(item[0]) << 24 | std::size_t(item[1]) << 16 | std::size_t(item[2]) << 8 | item[3];
  if (offset > item.size() - 4) return {};
  return read_exif_tiff(item.data() + 4 + offset, item.size() - 4 - offset);
}

}  // namespace

std::optional<HeifPhoto> decode_heif(const std::vector<std::uint8_t>& bytes, std::string& reason) {
  const std::unique_ptr<heif_context, ContextFree> context(heif_context_alloc());
  heif_error error = heif_context_read_from_memory_without_copy(context.get(), bytes.data(), bytes.size(), nullptr);
  heif_image_handle* raw_handle = nullptr;
  if (error.code == heif_error_Ok) error = heif_context_get_primary_image_handle(context.get(), &raw_handle);
  const std::unique_ptr<heif_image_handle, HandleRelease> handle(raw_handle);
  heif_image* raw_image = nullptr;
  if (error.code == heif_error_Ok) {
    error = heif_decode_image(handle.get(), &raw_image, heif_colorspace_RGB, heif_chroma_interleaved_RGB, nullptr);
  }
  const std::unique_ptr<heif_image, ImageRelease> image(raw_image);
  if (error.code != heif_error_Ok) {
    reason = std::string("cannot be decoded as HEIF (") + (error.message ? error.message : "libheif error") + ")";
    return std::nullopt;
  }
  int stride = 0;
  const std::uint8_t* plane = heif_image_get_plane_readonly(image.get(), heif_channel_interleaved, &stride);
  const int width = heif_image_get_width(image.get(), heif_channel_interleaved);
  const int height = heif_image_get_height(image.get(), heif_channel_interleaved);
  if (plane == nullptr || width <= 0 || height <= 0) {
    reason = "cannot be decoded as HEIF (no image data)";
    return std::nullopt;
  }
  HeifPhoto photo;
  const cv::Mat rgb(height, width, CV_8UC3, const_cast<std::uint8_t*>(plane), static_cast<std::size_t>(stride));
  cv::cvtColor(rgb, photo.image, cv::COLOR_RGB2BGR);  // a copy that outlives libheif's buffer
  photo.exif = exif_of(handle.get());
  return photo;
}

}  // namespace hos::sfm
