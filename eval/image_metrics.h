// Image similarity over a mask: PSNR and SSIM (Wang, Bovik, Sheikh,
// Simoncelli 2004) for 8-bit images.
#pragma once

#include <opencv2/core.hpp>

namespace hos::eval {

// Peak signal-to-noise ratio in dB over the pixels where mask != 0 (all
// pixels when mask is empty), all channels, peak 255. +infinity when the
// images are equal there. Throws std::invalid_argument for images of
// different size/type or an empty mask.
double masked_psnr(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask = cv::Mat());

// Mean SSIM over the masked pixels: the SSIM map (11x11 Gaussian window,
// sigma 1.5, K1 = 0.01, K2 = 0.03, L = 255) per channel, averaged over
// channels and masked pixels. 1 for identical images.
double masked_ssim(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask = cv::Mat());

// `render` with each channel mapped by the gain and offset that best fit it
// to `photo` over the masked pixels (least squares), saturated to 8 bits: a
// held-out photo's exposure and white balance are unknown to the pipeline,
// so PSNR after this measures what remains (geometry, texture detail).
// Throws as masked_psnr; a channel constant over the mask keeps gain 1.
cv::Mat exposure_matched(const cv::Mat& render, const cv::Mat& photo, const cv::Mat& mask = cv::Mat());

}  // namespace hos::eval
