// RateLimiter and the percentile helper.

#include "service/rate_limiter.h"

#include <catch2/catch.hpp>
#include <cstdint>
#include <vector>

namespace mvtrack::service {
namespace {

TEST_CASE("rate limiter allows one message per kind and interval, counting the rest", "[unit]") {
  RateLimiter limiter(1000);
  REQUIRE(limiter.Allow("a", 0).has_value());
  CHECK(*limiter.Allow("b", 10) == 0);  // kinds are independent
  CHECK_FALSE(limiter.Allow("a", 10).has_value());
  CHECK_FALSE(limiter.Allow("a", 999).has_value());
  const auto next = limiter.Allow("a", 1000);
  REQUIRE(next.has_value());
  CHECK(*next == 2);  // two suppressed since the last one
  CHECK(limiter.suppressed_total() == 2);
  limiter.SetInterval(10);
  CHECK(*limiter.Allow("a", 1010) == 0);
}

TEST_CASE("nearest-rank percentiles", "[unit]") {
  std::vector<std::int64_t> empty;
  CHECK(NearestRankPercentile(&empty, 0.5) == 0);
  std::vector<std::int64_t> v;
  for (std::int64_t i = 100; i >= 1; --i) v.push_back(i);  // 1..100, reversed
  CHECK(NearestRankPercentile(&v, 0.5) == 50);
  CHECK(NearestRankPercentile(&v, 0.99) == 99);
  CHECK(NearestRankPercentile(&v, 1.0) == 100);
  CHECK(NearestRankPercentile(&v, 0.0) == 1);
  std::vector<std::int64_t> one = {7};
  CHECK(NearestRankPercentile(&one, 0.99) == 7);
}

}  // namespace
}  // namespace mvtrack::service
