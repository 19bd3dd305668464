#include "core/median.h"

#include <catch2/catch.hpp>
#include <vector>

namespace mvtrack::core {
namespace {

TEST_CASE("MedianInPlace: the middle value, of an even count the mean of the two middle ones",
          "[unit]") {
  std::vector<double> odd = {5.0, 1.0, 4.0, 2.0, 3.0};
  CHECK(MedianInPlace(&odd) == 3.0);
  std::vector<double> even = {10.0, 0.1, 0.3, 0.2};
  CHECK(MedianInPlace(&even) == Approx(0.25));
  std::vector<double> one = {7.5};
  CHECK(MedianInPlace(&one) == 7.5);
  // A few far values do not move it.
  std::vector<double> spiked = {0.1, 0.1, 0.1, 0.1, 2.5, 2.5, 0.1};
  CHECK(MedianInPlace(&spiked) == 0.1);
}

}  // namespace
}  // namespace mvtrack::core
