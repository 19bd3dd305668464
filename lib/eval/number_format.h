#pragma once
/// @file
/// Locale-independent fixed-precision number formatting shared by the evaluation reports
/// (protocol strings, tables, JSON). Internal helpers; stateless.

#include <string>

namespace mvtrack::eval::internal {

/// `value` with exactly `precision` digits after the point ("0.500"), via std::to_chars (never
/// the C locale). Values that round to zero print without a sign ("0.000", never "-0.000").
/// NaN prints "nan", infinities "inf" / "-inf". `precision` is clamped to [0, 17].
std::string FormatFixed(double value, int precision);

}  // namespace mvtrack::eval::internal
