#pragma once
/// @file
/// Locale-independent fixed-precision number formatting shared by the evaluation reports
/// (protocol strings, tables, JSON), and the ratio their rates are. Internal helpers; stateless.

#include <cstdint>
#include <limits>
#include <string>

namespace mvtrack::eval::internal {

/// `value` with exactly `precision` digits after the point ("0.500"), via std::to_chars (never
/// the C locale). Values that round to zero print without a sign ("0.000", never "-0.000").
/// NaN prints "nan", infinities "inf" / "-inf". `precision` is clamped to [0, 17].
std::string FormatFixed(double value, int precision);

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// num / den; NaN when den is 0 (a rate of nothing: printed "nan", not 0).
inline double Ratio(std::int64_t num, std::int64_t den) {
  if (den == 0) return kNaN;
  return static_cast<double>(num) / static_cast<double>(den);
}

}  // namespace mvtrack::eval::internal
