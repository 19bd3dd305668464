#include "service/rate_limiter.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"

namespace mvtrack::service {

RateLimiter::RateLimiter(std::int64_t interval_us) : interval_us_(interval_us) {
  MVTRACK_CHECK(interval_us > 0);
}

std::optional<std::int64_t> RateLimiter::Allow(const std::string& kind, std::int64_t now_us) {
  std::lock_guard<std::mutex> lock(mu_);
  auto [it, inserted] = entries_.try_emplace(kind);
  Entry& e = it->second;
  if (inserted || now_us - e.last_us >= interval_us_) {
    const std::int64_t suppressed = e.suppressed;
    e.last_us = now_us;
    e.suppressed = 0;
    return suppressed;
  }
  ++e.suppressed;
  ++suppressed_total_;
  return std::nullopt;
}

void RateLimiter::SetInterval(std::int64_t interval_us) {
  MVTRACK_CHECK(interval_us > 0);
  std::lock_guard<std::mutex> lock(mu_);
  interval_us_ = interval_us;
}

std::int64_t RateLimiter::suppressed_total() const {
  std::lock_guard<std::mutex> lock(mu_);
  return suppressed_total_;
}

std::int64_t NearestRankPercentile(std::vector<std::int64_t>* samples, double q) {
  if (samples->empty()) return 0;
  MVTRACK_CHECK(q >= 0.0 && q <= 1.0);
  const double n = static_cast<double>(samples->size());
  std::size_t rank = static_cast<std::size_t>(std::ceil(q * n));
  if (rank < 1) rank = 1;
  const auto nth = samples->begin() + static_cast<std::ptrdiff_t>(rank - 1);
  std::nth_element(samples->begin(), nth, samples->end());
  return *nth;
}

}  // namespace mvtrack::service
