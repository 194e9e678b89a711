#include "eval/image_metrics.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hos::eval {
namespace {

cv::Mat gradient_image() {
  cv::Mat img(64, 80, CV_8UC3);
  for (int y = 0; y < img.rows; ++y) {
    for (int x = 0; x < img.cols; ++x) img.at<cv::Vec3b>(y, x) = cv::Vec3b(x * 3 + 10, y * 3 + 10, 100);
  }
  return img;
}

TEST(Psnr, IdenticalImagesAreInfinite) {
  const cv::Mat a = gradient_image();
  EXPECT_TRUE(std::isinf(masked_psnr(a, a)));
}

TEST(Psnr, KnownNoiseGivesAnalyticValue) {
  const cv::Mat a = gradient_image();
  cv::Mat b = a.clone();
  // +-5 on a checkerboard: MSE = 25 exactly (no clipping: values in [10, 247]).
  for (int y = 0; y < b.rows; ++y) {
    for (int x = 0; x < b.cols; ++x) {
      for (int c = 0; c < 3; ++c)
        b.at<cv::Vec3b>(y, x)[c] = cv::saturate_cast<uchar>(a.at<cv::Vec3b>(y, x)[c] + ((x + y) % 2 ? 5 : -5));
    }
  }
  cv::Mat clipped;
  cv::absdiff(a, b, clipped);
  ASSERT_EQ(cv::countNonZero(clipped.reshape(1) != 5), 0) << "test image must not clip";
  EXPECT_NEAR(masked_psnr(a, b), 10.0 * std::log10(255.0 * 255.0 / 25.0), 1e-9);
}

TEST(Psnr, MaskRestrictsThePixels) {
  const cv::Mat a = gradient_image();
  cv::Mat b = a.clone();
  b(cv::Rect(0, 0, 40, 64)).setTo(cv::Scalar(0, 0, 0));  // ruin the left half
  cv::Mat mask = cv::Mat::zeros(a.size(), CV_8U);
  mask(cv::Rect(40, 0, 40, 64)).setTo(255);
  EXPECT_TRUE(std::isinf(masked_psnr(a, b, mask)));
  EXPECT_LT(masked_psnr(a, b), 20.0);
  EXPECT_THROW(masked_psnr(a, b, cv::Mat::zeros(a.size(), CV_8U)), std::invalid_argument);
  EXPECT_THROW(masked_psnr(a, cv::Mat(10, 10, CV_8UC3)), std::invalid_argument);
}

TEST(Ssim, IdenticalIsOneAndDistortionLowersIt) {
  const cv::Mat a = gradient_image();
  EXPECT_NEAR(masked_ssim(a, a), 1.0, 1e-12);
  cv::Mat noisy = a.clone();
  cv::RNG rng(1);
  cv::Mat noise(a.size(), CV_8UC3);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 40);
  cv::add(a, noise, noisy);
  const double s = masked_ssim(a, noisy);
  EXPECT_LT(s, 0.95);
  EXPECT_GT(s, 0.0);
}

TEST(Ssim, ConstantImagesFollowTheLuminanceTerm) {
  // Flat images: sigma = 0, so SSIM = (2 mu_a mu_b + C1) / (mu_a^2 + mu_b^2 + C1).
  const cv::Mat a(32, 32, CV_8UC1, cv::Scalar(100)), b(32, 32, CV_8UC1, cv::Scalar(150));
  const double c1 = std::pow(0.01 * 255, 2);
  EXPECT_NEAR(masked_ssim(a, b), (2 * 100.0 * 150.0 + c1) / (100.0 * 100.0 + 150.0 * 150.0 + c1), 1e-9);
}

}  // namespace
}  // namespace hos::eval
