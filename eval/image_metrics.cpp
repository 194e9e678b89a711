#include "eval/image_metrics.h"

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

namespace hos::eval {
namespace {

cv::Mat checked_mask(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask) {
  if (a.empty() || a.size() != b.size() || a.type() != b.type()) {
    throw std::invalid_argument("image metrics: images must be non-empty and of the same size and type");
  }
  if (a.depth() != CV_8U) throw std::invalid_argument("image metrics: 8-bit images expected");
  cv::Mat m = mask.empty() ? cv::Mat(a.size(), CV_8U, cv::Scalar(255)) : mask;
  if (m.size() != a.size() || m.type() != CV_8U) {
    throw std::invalid_argument("image metrics: the mask must be CV_8U and of the image size");
  }
  if (cv::countNonZero(m) == 0) throw std::invalid_argument("image metrics: the mask is empty");
  return m;
}

}  // namespace

double masked_psnr(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask) {
  const cv::Mat m = checked_mask(a, b, mask);
  cv::Mat fa, fb;
  a.convertTo(fa, CV_64F);
  b.convertTo(fb, CV_64F);
  cv::Mat diff = fa - fb;
  diff = diff.mul(diff);
  const cv::Scalar sum = cv::sum(diff.setTo(cv::Scalar::all(0), m == 0));
  double total = 0.0;
  for (int c = 0; c < a.channels(); ++c) total += sum[c];
  const double mse = total / (static_cast<double>(cv::countNonZero(m)) * a.channels());
  if (mse == 0.0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(255.0 * 255.0 / mse);
}

double masked_ssim(const cv::Mat& a, const cv::Mat& b, const cv::Mat& mask) {
  const cv::Mat m = checked_mask(a, b, mask);
  // Per channel: a bare double added to a multi-channel matrix is ambiguous
  // to OpenCV (it warns on every call).
  const cv::Scalar c1 = cv::Scalar::all((0.01 * 255) * (0.01 * 255)), c2 = cv::Scalar::all((0.03 * 255) * (0.03 * 255));
  cv::Mat x, y;
  a.convertTo(x, CV_64F);
  b.convertTo(y, CV_64F);
  const auto blur = [](const cv::Mat& in) {
    cv::Mat out;
    cv::GaussianBlur(in, out, cv::Size(11, 11), 1.5, 1.5, cv::BORDER_REFLECT);
    return out;
  };
  const cv::Mat mx = blur(x), my = blur(y);
  const cv::Mat mx2 = mx.mul(mx), my2 = my.mul(my), mxy = mx.mul(my);
  const cv::Mat sx2 = blur(x.mul(x)) - mx2, sy2 = blur(y.mul(y)) - my2, sxy = blur(x.mul(y)) - mxy;
  cv::Mat num = (2 * mxy + c1).mul(2 * sxy + c2);
  cv::Mat den = (mx2 + my2 + c1).mul(sx2 + sy2 + c2);
  cv::Mat map;
  cv::divide(num, den, map);
  const cv::Scalar sum = cv::sum(map.setTo(cv::Scalar::all(0), m == 0));
  double total = 0.0;
  for (int c = 0; c < a.channels(); ++c) total += sum[c];
  return total / (static_cast<double>(cv::countNonZero(m)) * a.channels());
}

cv::Mat exposure_matched(const cv::Mat& render, const cv::Mat& photo, const cv::Mat& mask) {
  const cv::Mat m = checked_mask(render, photo, mask);
  std::vector<cv::Mat> r, p;
  cv::split(render, r);
  cv::split(photo, p);
  for (std::size_t c = 0; c < r.size(); ++c) {
    // Least squares of photo = gain * render + offset over the mask.
    cv::Scalar mean_r, std_r;
    cv::meanStdDev(r[c], mean_r, std_r, m);
    const cv::Scalar mean_p = cv::mean(p[c], m);
    cv::Mat fr, fp;
    r[c].convertTo(fr, CV_64F, 1.0, -mean_r[0]);
    p[c].convertTo(fp, CV_64F, 1.0, -mean_p[0]);
    const double covariance = cv::mean(fr.mul(fp), m)[0];
    const double variance = std_r[0] * std_r[0];
    const double gain = variance > 0.0 ? covariance / variance : 1.0;
    r[c].convertTo(r[c], CV_8U, gain, mean_p[0] - gain * mean_r[0]);
  }
  cv::Mat out;
  cv::merge(r, out);
  return out;
}

}  // namespace hos::eval
