#pragma once
/// @file
/// FramePeriod: a stream's frame period measured from capture times, robust to a few bad ones.
/// Pure, single-owner, single-threaded; the estimate depends only on the calls.

#include <array>
#include <cstddef>
#include <utility>

#include "core/types.h"

namespace mvtrack::tracker {

/// Remembers the (frame, utime) of the latest frames of a stream and estimates the period as the
/// median over up to 32 consecutive ones of utime difference / frame difference (pairs whose
/// frame or utime does not increase are ignored), so a skewed camera or a clock step among them
/// does not move it; `kDefaultSeconds` (1/30 s) before two usable frames; clamped to
/// [0.1 ms, 60 s].
class FramePeriod {
 public:
  static constexpr double kDefaultSeconds = 1.0 / 30.0;
  static constexpr std::size_t kFrames = 32;

  /// Records one frame (frames in stream order).
  void Add(FrameIndex frame, Utime utime);
  /// Forgets every frame (a new stream may run at another rate).
  void Clear() { size_ = 0; }
  /// Frames remembered (at most kFrames).
  std::size_t size() const { return size_; }
  /// The estimate, seconds per frame. No allocation (a ring buffer; it runs per camera-frame).
  double Seconds() const;

 private:
  std::array<std::pair<FrameIndex, Utime>, kFrames> frames_{};  // ring, oldest at `first_`
  std::size_t first_ = 0;
  std::size_t size_ = 0;
};

}  // namespace mvtrack::tracker
