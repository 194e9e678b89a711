// mvs/window_ncc.*: the photo-consistency kernels against a direct
// double-precision weighted NCC, and the AVX2 kernel against the portable one.
#include "mvs/window_ncc.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

namespace hos::mvs {
namespace {

constexpr int kNccWidth = 96, kNccHeight = 80;

// Random gray values on the photos' 8-bit grid.
cv::Mat random_gray(std::mt19937& rng) {
  cv::Mat gray(kNccHeight, kNccWidth, CV_32F);
  std::uniform_int_distribution<int> value(0, 255);
  for (int y = 0; y < kNccHeight; ++y) {
    for (int x = 0; x < kNccWidth; ++x) gray.at<float>(y, x) = float(value(rng)) / 255.0f;
  }
  return gray;
}

// A window of radius r sampled every step pixels, offsets padded as the
// kernels want them, and one reference pixel's weights, centred values and
// variance (random positive weights: the kernels do not care how they
// were made).
struct Window {
  std::vector<float> ox, oy, weights, centred;
  NccWindow window;
  NccReference ref;
};

Window make_window(const cv::Mat& ref_gray, int x, int y, int radius, int step, std::mt19937& rng) {
  Window w;
  for (int dy = -radius; dy <= radius; dy += step) {
    for (int dx = -radius; dx <= radius; dx += step) {
      w.ox.push_back(float(dx));
      w.oy.push_back(float(dy));
    }
  }
  const int count = static_cast<int>(w.ox.size());
  std::uniform_real_distribution<double> weight(0.2, 1.0);
  std::vector<double> wt(count);
  double sum = 0, mean = 0;
  for (int j = 0; j < count; ++j) sum += wt[j] = weight(rng);
  for (int j = 0; j < count; ++j) mean += wt[j] / sum * ref_gray.at<float>(y + int(w.oy[j]), x + int(w.ox[j]));
  double var = 0;
  for (int j = 0; j < count; ++j) {
    const double d = ref_gray.at<float>(y + int(w.oy[j]), x + int(w.ox[j])) - mean;
    w.weights.push_back(float(wt[j] / sum));
    w.centred.push_back(float(wt[j] / sum * d));
    var += wt[j] / sum * d * d;
  }
  while (w.ox.size() % kNccLanes != 0) {
    w.ox.push_back(0.0f);
    w.oy.push_back(0.0f);
  }
  const int last_offset = 2 * radius / step * step - radius;  // the window's last sample, a multiple of step
  w.window = {w.ox.data(), w.oy.data(), count, float(-radius), float(last_offset)};
  w.ref.x = x + 0.5f;
  w.ref.y = y + 0.5f;
  w.ref.centre_value = ref_gray.at<float>(y, x);
  w.ref.weights = w.weights.data();
  w.ref.centred = w.centred.data();
  w.ref.variance = float(var);
  return w;
}

// The weighted NCC written out in doubles on the float image: the truth the
// kernels approximate; 2 where a sample leaves the image.
double direct_cost(const Window& w, const std::array<float, 9>& h, const cv::Mat& src) {
  double sw = 0, sws = 0, swss = 0, cov = 0;
  for (int j = 0; j < w.window.count; ++j) {
    const double px = w.ref.x + w.ox[j], py = w.ref.y + w.oy[j];
    const double z = h[6] * px + h[7] * py + h[8];
    if (!(z > 1e-6)) return kWindowUnseen;
    const double u = (h[0] * px + h[1] * py + h[2]) / z - 0.5, v = (h[3] * px + h[4] * py + h[5]) / z - 0.5;
    if (!(u >= 0 && v >= 0 && u < src.cols - 1 && v < src.rows - 1)) return kWindowUnseen;
    const int x0 = int(u), y0 = int(v);
    const double fx = u - x0, fy = v - y0;
    const double value = (1 - fy) * ((1 - fx) * src.at<float>(y0, x0) + fx * src.at<float>(y0, x0 + 1)) +
                         fy * ((1 - fx) * src.at<float>(y0 + 1, x0) + fx * src.at<float>(y0 + 1, x0 + 1));
    sw += w.weights[j];
    sws += w.weights[j] * value;
    swss += w.weights[j] * value * value;
    cov += w.centred[j] * value;
  }
  const double var_s = swss / sw - (sws / sw) * (sws / sw);
  if (var_s <= 1e-10 || w.ref.variance <= 1e-10) return 2.0;
  return 1.0 - cov / std::sqrt(w.ref.variance * var_s);
}

// A homography near a translation, with some rotation, scale, shear and
// perspective.
std::array<float, 9> random_homography(std::mt19937& rng) {
  std::uniform_real_distribution<float> small(-0.15f, 0.15f), shift(-6.0f, 6.0f), tilt(-4e-4f, 4e-4f);
  return {1 + small(rng), small(rng), shift(rng), small(rng), 1 + small(rng), shift(rng), tilt(rng), tilt(rng), 1.0f};
}

TEST(WindowNcc, PortableKernelEqualsTheDirectWeightedNcc) {
  std::mt19937 rng(3);
  const cv::Mat ref = random_gray(rng), src_gray = random_gray(rng);
  const QuadImage src = make_quad_image(src_gray);
  int scored = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const int radius = 1 + trial % 5, step = 1 + trial % radius;
    std::uniform_int_distribution<int> px(radius, kNccWidth - 1 - radius), py(radius, kNccHeight - 1 - radius);
    const Window w = make_window(ref, px(rng), py(rng), radius, step, rng);
    const auto h = random_homography(rng);
    const double truth = direct_cost(w, h, src_gray);
    const float cost = window_ncc_portable(w.window, w.ref, h.data(), src);
    if (truth == 2.0 || truth == kWindowUnseen) {
      EXPECT_EQ(cost, static_cast<float>(truth)) << "trial " << trial;
    } else {
      ++scored;
      EXPECT_NEAR(cost, truth, 1e-4) << "trial " << trial;
    }
  }
  EXPECT_GT(scored, 1000);
}

TEST(WindowNcc, Avx2KernelEqualsThePortableOne) {
  if (!window_ncc_avx2_available()) GTEST_SKIP() << "no AVX2 on this CPU";
  std::mt19937 rng(5);
  const cv::Mat ref = random_gray(rng), src_gray = random_gray(rng);
  const QuadImage src = make_quad_image(src_gray);
  int scored = 0;
  for (int trial = 0; trial < 5000; ++trial) {
    const int radius = 1 + trial % 7, step = 1 + trial % radius;
    std::uniform_int_distribution<int> px(radius, kNccWidth - 1 - radius), py(radius, kNccHeight - 1 - radius);
    const Window w = make_window(ref, px(rng), py(rng), radius, step, rng);
    const auto h = random_homography(rng);
    const float portable = window_ncc_portable(w.window, w.ref, h.data(), src);
    const float avx2 = window_ncc_avx2(w.window, w.ref, h.data(), src);
    // The portable kernel checks the corners, the AVX2 one every sample:
    // the same test but for rounding at the image's edge.
    if (portable >= 2.0f || avx2 >= 2.0f) continue;
    ++scored;
    EXPECT_NEAR(avx2, portable, 1e-5) << "trial " << trial;
  }
  EXPECT_GT(scored, 2500);
}

TEST(WindowNcc, IdenticalWindowsCostZeroAndWindowsLeavingTheImageUnseen) {
  std::mt19937 rng(9);
  const cv::Mat gray = random_gray(rng);
  const QuadImage src = make_quad_image(gray);
  const Window w = make_window(gray, 40, 30, 4, 2, rng);
  const std::array<float, 9> identity = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const std::array<float, 9> far_right = {1, 0, 60, 0, 1, 0, 0, 0, 1};  // the window's right column leaves
  const std::array<float, 9> behind = {1, 0, 0, 0, 1, 0, 0, 0, -1};     // z < 0
  for (const WindowNccFunction kernel : {&window_ncc_portable, best_window_ncc()}) {
    EXPECT_NEAR(kernel(w.window, w.ref, identity.data(), src), 0.0f, 1e-5f);
    EXPECT_EQ(kernel(w.window, w.ref, far_right.data(), src), kWindowUnseen);
    EXPECT_EQ(kernel(w.window, w.ref, behind.data(), src), kWindowUnseen);
  }
}

}  // namespace
}  // namespace hos::mvs
