#include "eval/number_format.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>

namespace mvtrack::eval::internal {

std::string FormatFixed(double value, int precision) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0.0 ? "inf" : "-inf";
  const int p = std::clamp(precision, 0, 17);
  // |value| < half a unit of the last digit rounds to zero: print it as an unsigned zero.
  if (std::abs(value) < 0.5 * std::pow(10.0, -p)) value = 0.0;
  // Enough for 309 integer digits, the point and 17 decimals.
  std::array<char, 340> buffer{};
  const auto [end, ec] = std::to_chars(
      buffer.data(), buffer.data() + buffer.size(), value, std::chars_format::fixed, p);
  if (ec != std::errc()) return "nan";
  std::string text(buffer.data(), end);
  // Rounding can still produce "-0.00" for values just above the cut-off in magnitude.
  if (text.front() == '-' && text.find_first_not_of("-0.") == std::string::npos) text.erase(0, 1);
  return text;
}

}  // namespace mvtrack::eval::internal
