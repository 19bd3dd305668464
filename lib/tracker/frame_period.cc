#include "tracker/frame_period.h"

#include <algorithm>

namespace mvtrack::tracker {

void FramePeriod::Add(FrameIndex frame, Utime utime) {
  if (size_ < kFrames) {
    frames_[(first_ + size_++) % kFrames] = {frame, utime};
  } else {
    frames_[first_] = {frame, utime};  // replaces the oldest
    first_ = (first_ + 1) % kFrames;
  }
}

double FramePeriod::Seconds() const {
  std::array<double, kFrames> periods;
  std::size_t n = 0;
  for (std::size_t i = 1; i < size_; ++i) {
    const auto& [f0, u0] = frames_[(first_ + i - 1) % kFrames];
    const auto& [f1, u1] = frames_[(first_ + i) % kFrames];
    // In double: differences of arbitrary int64 values may not fit in an int64.
    const double df = static_cast<double>(f1) - static_cast<double>(f0);
    const double du = static_cast<double>(u1) - static_cast<double>(u0);
    if (df >= 1.0 && du > 0.0) periods[n++] = du * 1e-6 / df;
  }
  if (n == 0) return kDefaultSeconds;
  const auto end = periods.begin() + static_cast<std::ptrdiff_t>(n);
  const auto mid = periods.begin() + static_cast<std::ptrdiff_t>(n / 2);
  std::nth_element(periods.begin(), mid, end);
  return std::clamp(*mid, 1e-4, 60.0);
}

}  // namespace mvtrack::tracker
