#include "core/median.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <random>
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

TEST_CASE("MedianInPlace: small and large samples give the sorted sample's middle exactly",
          "[unit]") {
  // Small samples are sorted by insertion, larger ones by nth_element: both must give the
  // value of the fully sorted sample, bit for bit, with ties and negative values.
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> level(-20, 20);
  for (std::size_t n = 1; n <= 3 * kSmallMedianCount; ++n) {
    for (int trial = 0; trial < 50; ++trial) {
      std::vector<double> v(n);
      for (double& x : v) x = 0.37 * level(rng);
      std::vector<double> sorted = v;
      std::sort(sorted.begin(), sorted.end());
      const double want = n % 2 == 1 ? sorted[n / 2] : 0.5 * (sorted[n / 2] + sorted[n / 2 - 1]);
      INFO("n " << n);
      REQUIRE(MedianInPlace(&v) == want);
    }
  }
}

}  // namespace
}  // namespace mvtrack::core
