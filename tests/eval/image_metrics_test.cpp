#include "eval/image_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

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

// A textured image with values in [20, 220] (no clipping under the maps below).
cv::Mat textured_image() {
  cv::Mat img(64, 80, CV_8UC3);
  for (int y = 0; y < img.rows; ++y) {
    for (int x = 0; x < img.cols; ++x) {
      img.at<cv::Vec3b>(y, x) =
          cv::Vec3b(20 + (x * 7 + y * 13) % 50 * 4, 20 + (x * 11 + y * 3) % 50 * 4, 20 + (x * 5 + y * 17) % 50 * 4);
    }
  }
  return img;
}

TEST(ExposureMatched, UndoesAGainAndOffsetPerChannelButNotAShift) {
  const cv::Mat photo = textured_image();
  // A render of another exposure and white balance: per-channel gain and offset.
  cv::Mat render;
  cv::transform(photo, render, cv::Matx34f(0.8f, 0, 0, 20, 0, 0.9f, 0, 5, 0, 0, 1.1f, -8));
  EXPECT_LT(masked_psnr(render, photo), 30.0);
  // Left: rounding to 8 bits (twice), under one grey level.
  EXPECT_GT(masked_psnr(exposure_matched(render, photo), photo), 45.0);
  // Pixels outside the mask do not take part in the fit.
  cv::Mat mask(photo.size(), CV_8U, cv::Scalar(255));
  mask.colRange(0, 20).setTo(0);
  cv::Mat spoiled = render.clone();
  spoiled.colRange(0, 20).setTo(cv::Scalar(255, 0, 255));
  EXPECT_GT(masked_psnr(exposure_matched(spoiled, photo, mask), photo, mask), 45.0);
  // A render two pixels off stays wrong: no gain and offset fix structure
  // (the fit can only pull an uncorrelated render towards the photo's mean).
  cv::Mat shifted;
  cv::warpAffine(photo, shifted, cv::Matx23f(1, 0, 2, 0, 1, 0), photo.size(), cv::INTER_NEAREST, cv::BORDER_REFLECT);
  EXPECT_LT(masked_psnr(exposure_matched(shifted, photo), photo), 20.0);
  // Bad input is refused as by masked_psnr.
  EXPECT_THROW(exposure_matched(render, cv::Mat(10, 10, CV_8UC3)), std::invalid_argument);
  EXPECT_THROW(exposure_matched(render, photo, cv::Mat::zeros(photo.size(), CV_8U)), std::invalid_argument);
}

}  // namespace
}  // namespace hos::eval
