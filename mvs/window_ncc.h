// PatchMatch's photo-consistency kernel: the bilaterally weighted NCC of a
// reference window against a source image warped by a plane's homography.
// Everything that depends on the reference window only (weights, centred
// values, variance) is computed once per reference pixel by the caller; the
// kernel projects the window's samples, looks them up bilinearly in the
// source and forms three weighted sums. The source holds 8-bit values in
// vertical pairs, so a bilinear lookup is one 32-bit load (and eight of them
// one AVX2 gather).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace hos::mvs {

// A source image for window sampling: per pixel (x, y) the bytes v(x, y)
// and v(x, y + 1) from low to high, each the gray value times 255 rounded
// (the photos' own 8 bits); the last row repeats itself. Two neighbouring
// pairs are a bilinear lookup's four values, read at once, in half the
// memory of a word per pixel (the lookups' cache misses are much of the
// matching time).
struct QuadImage {
  std::vector<std::uint16_t> pairs;  // width * height, and one more
  int width = 0, height = 0;
};

// gray: CV_32F in [0, 1].
QuadImage make_quad_image(const cv::Mat& gray);

// The window's sample offsets from its centre pixel; count samples, the
// arrays padded with zeros to a multiple of 8 (kNccLanes).
constexpr int kNccLanes = 8;
struct NccWindow {
  const float* offset_x = nullptr;
  const float* offset_y = nullptr;
  int count = 0;
  // Offsets of the window's extreme samples on each axis (its corners).
  float low = 0, high = 0;
};

// One reference pixel's window: its centre (pixel-centre coordinates),
// the centre's gray value, the bilateral weights (summing to 1), the
// weighted centred values w_j (r_j - mean) and their weighted variance;
// count values each.
struct NccReference {
  float x = 0, y = 0;
  float centre_value = 0;
  const float* weights = nullptr;
  const float* centred = nullptr;
  float variance = 0;
};

// What the kernels return when a sample of the warped window leaves the
// source image or lies behind its camera: the source does not see the
// window, which says nothing about the plane (unlike a poor match).
constexpr float kWindowUnseen = 4.0f;

// 1 - NCC of the reference window against src through the homography h
// (row-major 3x3, pixel-centre coordinates in and out), in [0, 2]; 2 if
// either window is flat; kWindowUnseen if the source does not see it.
using WindowNccFunction = float (*)(const NccWindow&, const NccReference&, const float* h, const QuadImage& src);

// Plain C++, for any CPU.
float window_ncc_portable(const NccWindow& window, const NccReference& ref, const float* h, const QuadImage& src);

// AVX2 and FMA, eight samples at a time; only call where
// window_ncc_avx2_available(). Equals the portable kernel up to rounding.
float window_ncc_avx2(const NccWindow& window, const NccReference& ref, const float* h, const QuadImage& src);
bool window_ncc_avx2_available();

// The fastest kernel this CPU runs.
WindowNccFunction best_window_ncc();

}  // namespace hos::mvs
