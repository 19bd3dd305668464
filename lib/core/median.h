#pragma once
/// @file
/// The median of a sample of doubles, as the refinement and linking stages use it (of an even
/// count: the mean of the two middle values). Pure, deterministic.

#include <algorithm>
#include <cstddef>
#include <vector>

#include "core/check.h"

namespace mvtrack::core {

/// The median of `values`, which it reorders (std::nth_element, O(n)). `values` must not be
/// empty (checked).
inline double MedianInPlace(std::vector<double>* values) {
  MVTRACK_CHECK(values != nullptr && !values->empty());
  std::vector<double>& v = *values;
  const std::size_t mid = v.size() / 2;
  const auto middle = v.begin() + static_cast<std::ptrdiff_t>(mid);
  std::nth_element(v.begin(), middle, v.end());
  if (v.size() % 2 == 1) return *middle;
  return 0.5 * (*middle + *std::max_element(v.begin(), middle));
}

}  // namespace mvtrack::core
