#pragma once
/// @file
/// Helpers of the viz tests: pixel access and colour comparison. Header-only.

#include <opencv2/core.hpp>

namespace mvtrack::viz::testing {

/// The BGR pixel of a CV_8UC3 image as a Scalar.
inline cv::Scalar PixelAt(const cv::Mat& image, cv::Point p) {
  const cv::Vec3b v = image.at<cv::Vec3b>(p);
  return cv::Scalar(v[0], v[1], v[2]);
}

/// Largest channel difference between two colours.
inline double ColorDistance(const cv::Scalar& a, const cv::Scalar& b) {
  double d = 0.0;
  for (int i = 0; i < 3; ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

}  // namespace mvtrack::viz::testing
