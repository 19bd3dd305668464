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
/// Samples of at most this many values are sorted by insertion instead (the temporal windows
/// of the refinement: 7 values by default, where std::nth_element's set-up dominates).
inline constexpr std::size_t kSmallMedianCount = 16;

inline double MedianInPlace(std::vector<double>* values) {
  MVTRACK_CHECK(values != nullptr && !values->empty());
  std::vector<double>& v = *values;
  const std::size_t n = v.size();
  const std::size_t mid = n / 2;
  if (n <= kSmallMedianCount) {
    // Insertion sort: the same order statistics as nth_element, so the same value.
    for (std::size_t i = 1; i < n; ++i) {
      const double x = v[i];
      std::size_t j = i;
      for (; j > 0 && x < v[j - 1]; --j) v[j] = v[j - 1];
      v[j] = x;
    }
    return n % 2 == 1 ? v[mid] : 0.5 * (v[mid] + v[mid - 1]);
  }
  const auto middle = v.begin() + static_cast<std::ptrdiff_t>(mid);
  std::nth_element(v.begin(), middle, v.end());
  if (n % 2 == 1) return *middle;
  return 0.5 * (*middle + *std::max_element(v.begin(), middle));
}

}  // namespace mvtrack::core
