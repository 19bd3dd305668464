#pragma once
/// @file
/// RateLimiter: decides whether a repeated log message of one kind may be written now, so a
/// flood of bad input produces one warning per kind and interval (with the number suppressed
/// since the previous one) instead of one per message.
///
/// Thread-safe: every method may be called from any thread. Time is passed in by the caller
/// (µs on any monotonic or wall time line), so the class reads no clock itself.

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace mvtrack::service {

/// Per-kind rate limiting of log messages; see the file comment.
class RateLimiter {
 public:
  /// At most one message per kind per `interval_us` (> 0).
  explicit RateLimiter(std::int64_t interval_us);

  /// Whether a message of `kind` may be logged at `now_us`. When it may, returns the number of
  /// messages of that kind suppressed since the last one allowed (0 for the first); otherwise
  /// counts one more suppressed message and returns nullopt.
  std::optional<std::int64_t> Allow(const std::string& kind, std::int64_t now_us);

  /// Changes the interval (configuration reload); > 0.
  void SetInterval(std::int64_t interval_us);

  /// Messages suppressed so far, all kinds together.
  std::int64_t suppressed_total() const;

 private:
  struct Entry {
    std::int64_t last_us = 0;
    std::int64_t suppressed = 0;
  };
  mutable std::mutex mu_;
  std::int64_t interval_us_;
  std::map<std::string, Entry> entries_;
  std::int64_t suppressed_total_ = 0;
};

/// The `q`-quantile (0 <= q <= 1) of `samples` by the nearest-rank method: the smallest value
/// such that at least ceil(q * n) samples are <= it (the minimum for q = 0). 0 when empty.
/// Reorders `samples`.
std::int64_t NearestRankPercentile(std::vector<std::int64_t>* samples, double q);

}  // namespace mvtrack::service
