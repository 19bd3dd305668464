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

/// The sender of a status message: tracker_status_t's instance_id and sequence.
struct TrackerStatusSource {
  std::string instance_id;
  std::int64_t sequence = 0;
};

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

/// The verdict of a site's stitcher status (site_status_t, issue 43): CRITICAL when no zone
/// is live (every zone NO_DATA or STALE) or the site flags NO_OUTPUT; WARNING when a zone has
/// a flag (each zone named with its flags, a degraded zone daemon with its own reasons) or the
/// site has another flag; otherwise OK.
HealthReport AssessSiteStatus(const transport::SiteStatus& status);

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

/// The worse of two verdicts, with the reasons of the worse one first (UNKNOWN counts as worse
/// than OK and WARNING, better than CRITICAL: a CRITICAL fact stays CRITICAL).
HealthReport Combine(HealthReport a, const HealthReport& b);

/// Who sends the status messages of one channel (issue 39). Every daemon draws a random
/// instance_id at start and numbers its statuses (sequence), so a consumer that keeps receiving
/// them tells apart
///   - a restart: a new instance follows the old one, which is not heard again: WARNING for the
///     window ("the tracker restarted: instance B replaced A"),
///   - two instances at once: an instance is heard again after another one was (a second
///     daemon publishing on the channel, or forged statuses): CRITICAL for the window (and
///     the "restart" it looked like at first is not reported),
///   - a sequence going backwards (or repeating) within an instance: a replayed or forged
///     status: CRITICAL for the window.
/// It cannot tell a forger who copies an instance id and keeps its sequence increasing while
/// the real daemon is silent (docs/OPERATING.md "Who can talk to it"). Single-threaded;
/// `now_s` is the consumer's steady clock, seconds. Memory: at most kMaxInstances instances.
class StatusSourceWatch {
 public:
  static constexpr std::size_t kMaxInstances = 16;
  /// Evidence older than `window_s` no longer counts (the consumer's staleness period).
  explicit StatusSourceWatch(double window_s) : window_s_(window_s) {}
  /// A status received at `now_s`.
  void Add(const TrackerStatusSource& source, double now_s);
  void Add(const transport::TrackerStatus& status, double now_s) {
    Add(TrackerStatusSource{status.instance_id, status.sequence}, now_s);
  }
  /// The verdict at `now_s`: OK without reasons when none of the above happened in the window.
  HealthReport Assess(double now_s) const;

 private:
  struct Instance {
    std::string id;
    std::int64_t last_sequence = 0;
  };
  struct Event {
    double at_s = -1e300;
    std::string what;
  };
  double window_s_;
  std::vector<Instance> instances_;  // least recently heard first
  Event restart_, conflict_, backwards_;
};

/// 16 lowercase hex digits from the system's entropy source: the instance id of a status
/// sender (tracker_status_t, site_status_t), different for every start.
std::string RandomInstanceId();

/// The daemon's systemd status line, e.g. "tracking: 3/3 cameras, 30.0 fps, 4 tracks (3
/// confirmed), OK" or "... WARNING: camera 2 CLOCK_OFFSET", with `fps` (FrameRateMeter).
std::string NotifyStatusLine(const transport::TrackerStatus& status, double fps);

}  // namespace mvtrack::service
