#include "mvs/window_ncc.h"

#include <algorithm>
#include <cmath>

#if defined(__GNUC__) && defined(__x86_64__)
#include <immintrin.h>
#define HOS_NCC_AVX2 1
#endif

namespace hos::mvs {
namespace {

// Largest window: radius 15 (the option's bound), every pixel, padded.
constexpr int kMaxSamples = 31 * 31 + kNccLanes;

// 1 - NCC from the weighted sums of the source values (shifted by the
// reference centre, which keeps the float sums of squares small when the
// windows match): sum w s, sum w s^2 and sum w (r - mean_r) s.
float ncc_from_sums(float ss, float sss, float cov, float var_r) {
  const float var_s = sss - ss * ss;
  if (!(var_s > 1e-10f) || !(var_r > 1e-10f)) return 2.0f;
  return 1.0f - cov / std::sqrt(var_r * var_s);
}

// Eight partial sums added pairwise in the order of the AVX2 kernel's
// horizontal sum.
float lane_sum(const float* v) {
  const float a0 = v[0] + v[4], a1 = v[1] + v[5], a2 = v[2] + v[6], a3 = v[3] + v[7];
  const float b0 = a0 + a2, b1 = a1 + a3;
  return b0 + b1;
}

}  // namespace

QuadImage make_quad_image(const cv::Mat& gray) {
  CV_Assert(gray.type() == CV_32F);
  QuadImage image;
  image.width = gray.cols;
  image.height = gray.rows;
  const int w = gray.cols, h = gray.rows;
  std::vector<std::uint8_t> bytes(std::size_t(w) * h);
  for (int y = 0; y < h; ++y) {
    const float* row = gray.ptr<float>(y);
    for (int x = 0; x < w; ++x) {
      const float v = row[x] > 0.0f ? std::min(row[x], 1.0f) : 0.0f;  // NaN -> 0
      bytes[std::size_t(y) * w + x] = static_cast<std::uint8_t>(std::lround(v * 255.0f));
    }
  }
  // One more pair: a 32-bit read at the last pixel stays inside.
  image.pairs.assign(bytes.size() + 1, 0);
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* top = &bytes[std::size_t(y) * w];
    const std::uint8_t* bottom = &bytes[std::size_t(std::min(y + 1, h - 1)) * w];
    for (int x = 0; x < w; ++x) {
      image.pairs[std::size_t(y) * w + x] = static_cast<std::uint16_t>(top[x] | bottom[x] << 8U);
    }
  }
  return image;
}

float window_ncc_portable(const NccWindow& window, const NccReference& ref, const float* h, const QuadImage& src) {
  const float W = static_cast<float>(src.width - 1), Hh = static_cast<float>(src.height - 1);
  const float cx = h[0] * ref.x + h[1] * ref.y + h[2];
  const float cy = h[3] * ref.x + h[4] * ref.y + h[5];
  const float cz = h[6] * ref.x + h[7] * ref.y + h[8];
  // The homography's z is linear over the window: positive at the corners
  // means positive everywhere, and the image of the window is then the
  // convex hull of its corners' images, so checking the corners suffices.
  for (const float oy : {window.low, window.high}) {
    for (const float ox : {window.low, window.high}) {
      const float mz = cz + ox * h[6] + oy * h[7];
      if (!(mz > 1e-6f)) return kWindowUnseen;
      const float u = (cx + ox * h[0] + oy * h[1]) / mz - 0.5f, v = (cy + ox * h[3] + oy * h[4]) / mz - 0.5f;
      if (!(u >= 0 && v >= 0 && u < W && v < Hh)) return kWindowUnseen;
    }
  }
  const int max_x = src.width - 2, max_y = src.height - 2;
  // Eight partial sums added up as the AVX2 kernel's lanes are, so the two
  // kernels round alike.
  float ss[kNccLanes] = {}, sss[kNccLanes] = {}, cov[kNccLanes] = {};
  for (int j = 0; j < window.count; ++j) {
    const float ox = window.offset_x[j], oy = window.offset_y[j];
    const float iz = 1.0f / (cz + ox * h[6] + oy * h[7]);
    const float u = (cx + ox * h[0] + oy * h[1]) * iz - 0.5f, v = (cy + ox * h[3] + oy * h[4]) * iz - 0.5f;
    const int x0 = std::min(static_cast<int>(u), max_x), y0 = std::min(static_cast<int>(v), max_y);
    const float fx = u - static_cast<float>(x0), fy = v - static_cast<float>(y0);
    const std::uint16_t* pair = &src.pairs[std::size_t(y0) * src.width + x0];
    const float a = float(pair[0] & 0xFFU), b = float(pair[1] & 0xFFU), c = float(pair[0] >> 8U),
                d = float(pair[1] >> 8U);
    const float top = a + fx * (b - a), bottom = c + fx * (d - c);
    const float value = (top + fy * (bottom - top)) * (1.0f / 255.0f) - ref.centre_value;
    const float wv = ref.weights[j] * value;
    ss[j % kNccLanes] += wv;
    sss[j % kNccLanes] += wv * value;
    cov[j % kNccLanes] += ref.centred[j] * value;
  }
  return ncc_from_sums(lane_sum(ss), lane_sum(sss), lane_sum(cov), ref.variance);
}

#ifdef HOS_NCC_AVX2

namespace {

__attribute__((target("avx2,fma"))) inline float horizontal_sum(__m256 v) {
  __m128 s = _mm_add_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1));
  s = _mm_add_ps(s, _mm_movehl_ps(s, s));
  s = _mm_add_ss(s, _mm_movehdup_ps(s));
  return _mm_cvtss_f32(s);
}

}  // namespace

// Two passes: project every sample and check that all lie in the image (so
// no lookup leaves it), then gather, interpolate and sum.
__attribute__((target("avx2,fma"))) float window_ncc_avx2(const NccWindow& window,
                                                          const NccReference& ref,
                                                          const float* h,
                                                          const QuadImage& src) {
  const int blocks = (window.count + kNccLanes - 1) / kNccLanes;
  const __m256 cx = _mm256_set1_ps(h[0] * ref.x + h[1] * ref.y + h[2]);
  const __m256 cy = _mm256_set1_ps(h[3] * ref.x + h[4] * ref.y + h[5]);
  const __m256 cz = _mm256_set1_ps(h[6] * ref.x + h[7] * ref.y + h[8]);
  const __m256 h0 = _mm256_set1_ps(h[0]), h1 = _mm256_set1_ps(h[1]), h3 = _mm256_set1_ps(h[3]);
  const __m256 h4 = _mm256_set1_ps(h[4]), h6 = _mm256_set1_ps(h[6]), h7 = _mm256_set1_ps(h[7]);
  const __m256 half = _mm256_set1_ps(0.5f), zero = _mm256_setzero_ps(), min_z = _mm256_set1_ps(1e-6f);
  const __m256 W = _mm256_set1_ps(static_cast<float>(src.width - 1));
  const __m256 Hh = _mm256_set1_ps(static_cast<float>(src.height - 1));
  alignas(32) float us[kMaxSamples], vs[kMaxSamples];
  __m256 inside = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
  for (int b = 0; b < blocks; ++b) {
    const __m256 ox = _mm256_loadu_ps(window.offset_x + b * kNccLanes);
    const __m256 oy = _mm256_loadu_ps(window.offset_y + b * kNccLanes);
    // Without FMA, so the sample positions round as the portable kernel's:
    // on fine texture a position's last bit moves the NCC by 1e-5.
    const __m256 mx = _mm256_add_ps(_mm256_add_ps(cx, _mm256_mul_ps(ox, h0)), _mm256_mul_ps(oy, h1));
    const __m256 my = _mm256_add_ps(_mm256_add_ps(cy, _mm256_mul_ps(ox, h3)), _mm256_mul_ps(oy, h4));
    const __m256 mz = _mm256_add_ps(_mm256_add_ps(cz, _mm256_mul_ps(ox, h6)), _mm256_mul_ps(oy, h7));
    const __m256 iz = _mm256_div_ps(_mm256_set1_ps(1.0f), mz);
    const __m256 u = _mm256_sub_ps(_mm256_mul_ps(mx, iz), half), v = _mm256_sub_ps(_mm256_mul_ps(my, iz), half);
    inside = _mm256_and_ps(inside, _mm256_cmp_ps(mz, min_z, _CMP_GT_OQ));
    inside = _mm256_and_ps(inside, _mm256_cmp_ps(u, zero, _CMP_GE_OQ));
    inside = _mm256_and_ps(inside, _mm256_cmp_ps(v, zero, _CMP_GE_OQ));
    inside = _mm256_and_ps(inside, _mm256_cmp_ps(u, W, _CMP_LT_OQ));
    inside = _mm256_and_ps(inside, _mm256_cmp_ps(v, Hh, _CMP_LT_OQ));
    _mm256_store_ps(us + b * kNccLanes, u);
    _mm256_store_ps(vs + b * kNccLanes, v);
  }
  if (_mm256_movemask_ps(inside) != 0xFF) return kWindowUnseen;
  const __m256i max_x = _mm256_set1_epi32(src.width - 2), max_y = _mm256_set1_epi32(src.height - 2);
  const __m256i width = _mm256_set1_epi32(src.width), low_byte = _mm256_set1_epi32(0xFF);
  const __m256 to_unit = _mm256_set1_ps(1.0f / 255.0f), shift = _mm256_set1_ps(ref.centre_value);
  const int* pairs = reinterpret_cast<const int*>(src.pairs.data());
  __m256 ss = zero, sss = zero, cov = zero;
  for (int b = 0; b < blocks; ++b) {
    const __m256 u = _mm256_load_ps(us + b * kNccLanes), v = _mm256_load_ps(vs + b * kNccLanes);
    const __m256i x0 = _mm256_min_epi32(_mm256_cvttps_epi32(u), max_x);
    const __m256i y0 = _mm256_min_epi32(_mm256_cvttps_epi32(v), max_y);
    const __m256 fx = _mm256_sub_ps(u, _mm256_cvtepi32_ps(x0)), fy = _mm256_sub_ps(v, _mm256_cvtepi32_ps(y0));
    // Two pairs from (x0, y0): bytes v(x0, y0), v(x0, y0 + 1), v(x0 + 1, y0), v(x0 + 1, y0 + 1).
    const __m256i q = _mm256_i32gather_epi32(pairs, _mm256_add_epi32(_mm256_mullo_epi32(y0, width), x0), 2);
    const __m256 p00 = _mm256_cvtepi32_ps(_mm256_and_si256(q, low_byte));
    const __m256 p01 = _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(q, 8), low_byte));
    const __m256 p10 = _mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(q, 16), low_byte));
    const __m256 p11 = _mm256_cvtepi32_ps(_mm256_srli_epi32(q, 24));
    const __m256 top = _mm256_fmadd_ps(fx, _mm256_sub_ps(p10, p00), p00);
    const __m256 bottom = _mm256_fmadd_ps(fx, _mm256_sub_ps(p11, p01), p01);
    const __m256 value = _mm256_fmsub_ps(_mm256_fmadd_ps(fy, _mm256_sub_ps(bottom, top), top), to_unit, shift);
    __m256 weight, centred;
    const int left = window.count - b * kNccLanes;
    if (left >= kNccLanes) {
      weight = _mm256_loadu_ps(ref.weights + b * kNccLanes);
      centred = _mm256_loadu_ps(ref.centred + b * kNccLanes);
    } else {
      // The padding lanes weigh nothing (and are not read).
      const __m256i mask = _mm256_cmpgt_epi32(_mm256_set1_epi32(left), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
      weight = _mm256_maskload_ps(ref.weights + b * kNccLanes, mask);
      centred = _mm256_maskload_ps(ref.centred + b * kNccLanes, mask);
    }
    const __m256 wv = _mm256_mul_ps(weight, value);
    ss = _mm256_add_ps(ss, wv);
    sss = _mm256_fmadd_ps(wv, value, sss);
    cov = _mm256_fmadd_ps(centred, value, cov);
  }
  return ncc_from_sums(horizontal_sum(ss), horizontal_sum(sss), horizontal_sum(cov), ref.variance);
}

bool window_ncc_avx2_available() { return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"); }

#else

float window_ncc_avx2(const NccWindow& window, const NccReference& ref, const float* h, const QuadImage& src) {
  return window_ncc_portable(window, ref, h, src);
}

bool window_ncc_avx2_available() { return false; }

#endif

WindowNccFunction best_window_ncc() { return window_ncc_avx2_available() ? window_ncc_avx2 : window_ncc_portable; }

}  // namespace hos::mvs
