#include "viz/colors.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace mvtrack::viz {

cv::Scalar HsvToBgr(double hue_deg, double saturation, double value) {
  const double h = std::fmod(std::fmod(hue_deg, 360.0) + 360.0, 360.0) / 60.0;
  const double s = std::clamp(saturation, 0.0, 1.0);
  const double v = std::clamp(value, 0.0, 1.0);
  const double c = v * s;
  const double x = c * (1.0 - std::abs(std::fmod(h, 2.0) - 1.0));
  const double m = v - c;
  double r = 0.0, g = 0.0, b = 0.0;
  switch (static_cast<int>(h)) {
    case 0:
      r = c;
      g = x;
      break;
    case 1:
      r = x;
      g = c;
      break;
    case 2:
      g = c;
      b = x;
      break;
    case 3:
      g = x;
      b = c;
      break;
    case 4:
      r = x;
      b = c;
      break;
    default:
      r = c;
      b = x;
      break;
  }
  return cv::Scalar(
      std::round(255.0 * (b + m)), std::round(255.0 * (g + m)), std::round(255.0 * (r + m)));
}

cv::Scalar TrackColor(TrackId3D id) {
  constexpr double kInverseGoldenRatio = 0.6180339887498949;
  // Unsigned arithmetic: negative ids are well defined too.
  const double turns =
      static_cast<double>(static_cast<std::uint64_t>(id) % 1000003u) * kInverseGoldenRatio;
  return HsvToBgr(360.0 * (turns - std::floor(turns)), 0.85, 1.0);
}

cv::Scalar Fade(const cv::Scalar& color, const cv::Scalar& background, double amount) {
  const double a = std::clamp(amount, 0.0, 1.0);
  return (1.0 - a) * color + a * background;
}

}  // namespace mvtrack::viz
