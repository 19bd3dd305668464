#pragma once
/// @file
/// Clock: the only source of time in lib/pipeline. It measures latencies for the status
/// message and never drives a decision (windows are keyed by frame index, not by time), so
/// the pipeline's output never depends on it. Live use: SteadyClock; replay and tests:
/// ManualClock, advanced by the log's timestamps.

#include <atomic>
#include <cstdint>

namespace mvtrack::pipeline {

/// A monotonic microsecond clock. Implementations are thread-safe: NowMicros() may be called
/// from any thread concurrently.
class Clock {
 public:
  virtual ~Clock() = default;
  /// Current time in µs on this clock's own (monotonic) time line.
  virtual std::int64_t NowMicros() const = 0;
};

/// std::chrono::steady_clock in µs since an unspecified epoch. Thread-safe.
class SteadyClock final : public Clock {
 public:
  /// steady_clock::now() in µs.
  std::int64_t NowMicros() const override;
};

/// std::chrono::system_clock in µs since the Unix epoch (the wall clock of LCM message
/// timestamps such as tracks3d_t.publish_utime). Not monotonic: it follows clock adjustments;
/// use it to stamp messages, SteadyClock to measure durations. Thread-safe.
class SystemClock final : public Clock {
 public:
  /// system_clock::now() in µs since 1970-01-01T00:00:00Z.
  std::int64_t NowMicros() const override;
};

/// A clock that only moves when told to (log replay, tests). Thread-safe: any thread may read
/// it while one thread sets or advances it.
class ManualClock final : public Clock {
 public:
  /// Starts at `start_us`.
  explicit ManualClock(std::int64_t start_us = 0) : now_us_(start_us) {}

  /// The time last set.
  std::int64_t NowMicros() const override { return now_us_.load(std::memory_order_acquire); }
  /// Sets the time to `now_us` (may be any value; replay sets it to each event's utime).
  void SetMicros(std::int64_t now_us) { now_us_.store(now_us, std::memory_order_release); }
  /// Advances the time by `delta_us` (>= 0, checked).
  void AdvanceMicros(std::int64_t delta_us);

 private:
  std::atomic<std::int64_t> now_us_;
};

}  // namespace mvtrack::pipeline
