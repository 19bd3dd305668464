#include "pipeline/clock.h"

#include <chrono>

#include "core/check.h"

namespace mvtrack::pipeline {

std::int64_t SteadyClock::NowMicros() const {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

std::int64_t SystemClock::NowMicros() const {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

void ManualClock::AdvanceMicros(std::int64_t delta_us) {
  MVTRACK_CHECK_MSG(delta_us >= 0, "a ManualClock never goes back");
  now_us_.fetch_add(delta_us, std::memory_order_acq_rel);
}

}  // namespace mvtrack::pipeline
