#pragma once
/// @file
/// What a tracker_status_t means for an operator (issue 15): one health verdict with its reasons
/// (the monitoring-plugin levels OK / WARNING / CRITICAL / UNKNOWN), and the one-line summary the
/// daemon gives systemd (`sd_notify STATUS=`). Pure functions of the message; the consumers
/// (`mvtrack status`, `mvtrack web`'s /healthz, the daemon) add the age of the message.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "transport/codec.h"

namespace mvtrack::service {

/// Monitoring-plugin levels; the values are `mvtrack status`'s exit codes.
enum class Health { kOk = 0, kWarning = 1, kCritical = 2, kUnknown = 3 };

/// "OK", "WARNING", "CRITICAL", "UNKNOWN".
const char* ToString(Health health);

/// A verdict with the reasons for it, worst first.
struct HealthReport {
  Health health = Health::kUnknown;
  std::vector<std::string> reasons;  ///< empty when OK
};

/// "OK", or the level and its reasons: "WARNING: camera 2 CLOCK_OFFSET; LATENCY_HIGH".
std::string HealthLine(const HealthReport& report);

/// The daemon flags NO_OUTPUT (tracker_status_t::FLAG_NO_OUTPUT) when camera-frames keep
/// arriving but no frame has been published for this long, wall clock: longer than the output
/// gap of a healthy stream (a window step, at most about a second at the rates the frame counts
/// are scaled for, plus processing), short enough that the health turns CRITICAL within 5 s of
/// the output stopping with a status period of up to 2 s.
inline constexpr std::int64_t kNoOutputAfterUs = 3'000'000;

/// CRITICAL when fewer than two configured cameras deliver (a camera delivers when it has data
/// and is not flagged NO_DATA, STALE or CLOCK_OFFSET: excluded from tracking), or the tracker
/// reports BACKLOG, JOB_FAILURES or NO_OUTPUT; WARNING when any camera or the tracker has another
/// flag set (each camera's flags are named); otherwise OK.
HealthReport AssessStatus(const transport::TrackerStatus& status);

/// Cameras delivering (see AssessStatus).
int CamerasDelivering(const transport::TrackerStatus& status);

/// Output frames per second of the status period (num_latency_samples / period_us).
double FramesPerSecond(const transport::TrackerStatus& status);

/// The output frame rate over the last `horizon_us` of status messages: the advance of
/// last_frame over the advance of utime. The output comes in bursts of a window step, so one
/// status period (FramesPerSecond) swings between 0 and several times the true rate.
class FrameRateMeter {
 public:
  explicit FrameRateMeter(std::int64_t horizon_us = 5'000'000) : horizon_us_(horizon_us) {}
  /// Adds a status; returns the rate, frames per second (FramesPerSecond of `status` until two
  /// statuses at least a second apart are known; restarts when frames or time go backwards).
  double Add(const transport::TrackerStatus& status);

 private:
  std::int64_t horizon_us_;
  std::vector<std::pair<std::int64_t, std::int64_t>> history_;  // (utime, last_frame)
};

/// The daemon's systemd status line, e.g. "tracking: 3/3 cameras, 30.0 fps, 4 tracks (3
/// confirmed), OK" or "... WARNING: camera 2 CLOCK_OFFSET", with `fps` (FrameRateMeter).
std::string NotifyStatusLine(const transport::TrackerStatus& status, double fps);

}  // namespace mvtrack::service
