#pragma once
/// @file
/// The configuration of the daemon `mvtrackd`: one YAML document (format `mvtrack.daemon/1`)
/// naming the cameras and their calibration file, the LCM URLs and channels, the frame
/// synchronizer, threads, queue bounds, status, logging and the embedded `tracker:` options.
/// Every key is documented in docs/DAEMON.md and docs/examples/mvtrackd.yaml.
///
/// Loading is strict, like lib/config: unknown keys (with a did-you-mean suggestion), wrong
/// types, non-finite and out-of-range values and inconsistent combinations are
/// config::ConfigErrors naming the file, the line and column and the key path. Relative file
/// names inside the document (the calibration, file:// URLs are NOT rewritten) are resolved
/// against the directory of the configuration file.
///
/// Stateless functions and a plain value type; thread-compatible.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "analytics/site_analytics.h"
#include "config/config_error.h"
#include "core/types.h"
#include "geometry/camera_model.h"
#include "pipeline/camera_queue.h"
#include "tracker/options.h"

namespace mvtrack::service {

/// The value of the mandatory top-level `format` key of a daemon configuration.
inline constexpr std::string_view kDaemonConfigFormat = "mvtrack.daemon/1";

/// How camera-frames are grouped into synchronized frames.
enum class SyncMode {
  /// By camera_detections_t.frame (hardware-triggered cameras, or a frame counter shared by
  /// the detectors). The frame index is used as is.
  kFrameIndex,
  /// By capture utime: camera-frames whose utimes lie within `tolerance_us` of a frame's first
  /// camera-frame belong to it (free-running cameras). The synchronizer numbers the frames
  /// 0, 1, 2, ... in utime order; the incoming frame field is ignored.
  kUtime,
};

/// "frame_index" or "utime".
std::string_view SyncModeName(SyncMode mode);
/// Inverse of SyncModeName; nullopt for an unknown name.
std::optional<SyncMode> SyncModeFromName(std::string_view name);

/// Which detection channels the daemon subscribes to.
enum class ChannelMode {
  kPerCamera,  ///< MVTRACK_DETECTIONS_<id> for each configured camera
  kShared,     ///< the one shared channel MVTRACK_DETECTIONS
  kBoth,       ///< both conventions (the regex MVTRACK_DETECTIONS(_[0-9]+)?)
};

/// "per_camera", "shared" or "both".
std::string_view ChannelModeName(ChannelMode mode);
/// Inverse of ChannelModeName; nullopt for an unknown name.
std::optional<ChannelMode> ChannelModeFromName(std::string_view name);

/// Frame synchronizer parameters (see service::FrameSynchronizer). Times are capture time
/// (message utime), never wall-clock time, except idle_flush_s.
struct SyncOptions {
  SyncMode mode = SyncMode::kFrameIndex;  ///< grouping rule
  /// kUtime: a camera-frame joins a pending frame whose first utime is within this, µs, >= 0.
  std::int64_t tolerance_us = 5000;
  /// A pending frame is released once the newest capture utime seen is this far past it, even
  /// if an active camera has not delivered (the late-camera deadline), µs, > 0.
  std::int64_t deadline_us = 200000;
  /// A camera whose newest accepted utime is this far behind the newest utime of all cameras
  /// is silent: excluded (frames stop waiting for it) and flagged until it delivers again,
  /// µs, > 0.
  std::int64_t silent_after_us = 1000000;
  /// A camera-frame whose utime is more than this ahead of the stream's time (the quorum's,
  /// see FrameSynchronizer) is rejected as far-future, µs, > 0.
  std::int64_t max_future_us = 10000000;
  /// kFrameIndex: a camera-frame whose frame index is more than this ahead of the stream's
  /// frame (the quorum's) is rejected as far-future, frames, >= 1.
  std::int64_t max_frame_ahead = 30;
  /// Clock model: a camera whose capture times differ from the other cameras' (the median of
  /// its last 16 offsets to the quorum) by more than this is flagged CLOCK_OFFSET and its
  /// camera-frames are rejected until the offset is back within half of it, µs, > 0.
  std::int64_t clock_tolerance_us = 100000;
  /// kFrameIndex: likewise for frame indices that disagree with the quorum's (a frame counter
  /// running fast or reset alone), frames, >= 1.
  std::int64_t max_frame_offset = 10;
  /// A camera-frame less than this after the camera's previous accepted one (capture time) is
  /// dropped as flooding, µs, >= 0 (0 = off). On by default: 4 ms passes cameras up to 250 fps
  /// and stops a camera (or a forger using its id) sending many times its rate.
  std::int64_t min_frame_interval_us = 4000;
  /// A camera with this many consecutive time-order rejections (backwards, late, far-future)
  /// restarted: when more than half of the cameras with data did, the stream restarted
  /// (pending frames are released, the tracker ends its stream, and the next camera-frame
  /// starts a new one); a camera that restarted alone starts over alone, >= 1.
  int resync_after_rejections = 30;
  /// At most this many synchronized frames may be pending; more release the oldest early,
  /// >= 1 (bounds memory whatever the input).
  int max_pending_frames = 64;
  /// Wall-clock seconds without any input after which pending frames are released and the
  /// tracker's open windows are flushed (all cameras silent); 0 = never. The only wall-clock
  /// driven action; it never fires while messages keep arriving.
  double idle_flush_s = 5.0;
};

/// Everything in a daemon configuration file.
struct DaemonConfig {
  /// The file this was loaded from ("" when parsed from text without a file).
  std::string source;

  /// zone: the zone of a site this daemon tracks (issue 43, `mvtrack calib zones`), "" = none.
  /// A zone's output channels default to the site channels suffixed with the zone in upper case
  /// (MVTRACK_TRACKS_ZONE1, MVTRACK_STATUS_ZONE1, ...; config::ZoneChannel); output.* and
  /// analytics.* channels given explicitly are kept.
  std::string zone;

  /// cameras.calibration, resolved against the configuration file's directory.
  std::string calibration_path;
  /// The calibrated cameras in use: cameras.ids of the calibration (all when `ids` is absent),
  /// sorted by id.
  std::vector<geometry::CameraModel> cameras;

  /// input.lcm_url: where detections come from (udpm://..., file://...?speed=0, memq://).
  std::string input_url = "udpm://239.255.76.67:7667?ttl=0";
  /// input.channels: the subscription convention.
  ChannelMode channel_mode = ChannelMode::kBoth;
  /// input.max_message_bytes: larger messages are rejected unread.
  std::int64_t max_message_bytes = std::int64_t{1} << 20;
  /// input.max_detections: camera_detections_t.num_detections limit at decode time.
  int max_detections_per_message = 1000;
  /// input.lcm_queue_capacity: messages LCM may hold per subscription while the daemon's handler
  /// is busy (LCM drops the rest, in no counter); 0 = LcmQueueCapacity's default.
  int lcm_queue_capacity = 0;

  /// output.lcm_url: where tracks and status go; "" = the input URL, except for a file://
  /// input (read-only), where "" means no LCM output (use --record or --tracks-jsonl).
  std::string output_url;
  /// output.tracks_channel.
  std::string tracks_channel = "MVTRACK_TRACKS";
  /// output.status_channel.
  std::string status_channel = "MVTRACK_STATUS";
  /// output.provisional_channel: where the provisional layer goes (tracks3d_t with
  /// LAYER_PROVISIONAL, tracker::ProvisionalEstimator); "" = not computed, not published.
  std::string provisional_channel = "MVTRACK_TRACKS_NOW";
  /// output.status_period_s: status message period (wall clock), seconds, in [0.05, 3600].
  double status_period_s = 1.0;
  /// output.latency_limit_us: FLAG_LATENCY_HIGH above this p99 processing latency, µs, > 0.
  std::int64_t latency_limit_us = 2000000;

  /// sync: the frame synchronizer.
  SyncOptions sync;

  /// threads.workers: window-job worker threads; 0 = one per core.
  int workers = 0;
  /// threads.job_queue: window jobs waiting for a worker.
  int job_queue_capacity = 64;

  /// queues.camera_capacity: camera-frames waiting per camera thread.
  int camera_queue_capacity = 8;
  /// queues.camera_overflow: drop_oldest (live) or block (lossless; log playback).
  pipeline::OverflowPolicy camera_overflow = pipeline::OverflowPolicy::kDropOldest;
  /// queues.reorder_capacity: camera outputs ahead of the scheduler.
  int reorder_capacity = 256;
  /// queues.finalizer_capacity: steps pending for the finalizer thread.
  int finalizer_queue_capacity = 1024;

  /// logging.level: trace, debug, info, warn, error, critical or off.
  std::string log_level = "info";
  /// logging.repeat_interval_s: a repeated warning of one kind is logged at most once per
  /// interval (the suppressed count is reported with the next one), seconds, > 0.
  double log_repeat_interval_s = 10.0;

  /// analytics.site: the site file (regions and lines, docs/FORMATS.md "Site file"), resolved
  /// against the configuration file's directory; "" = no analytics.
  std::string site_path;
  /// The site loaded from site_path (empty when there is none).
  analytics::Site site;
  /// analytics.events_channel: where analytics_event_t messages go.
  std::string analytics_events_channel = "MVTRACK_ANALYTICS_EVENTS";
  /// analytics.counts_channel: where site_counts_t messages go.
  std::string site_counts_channel = "MVTRACK_SITE_COUNTS";
  /// state.directory: where the daemon keeps what must survive a restart (the track id
  /// reservation, service::IdReservation), resolved against the configuration file's
  /// directory; "" = $STATE_DIRECTORY (systemd's StateDirectory=) when mvtrackd runs under
  /// systemd, else nothing is kept and ids start at 1 each run.
  std::string state_directory;
  /// state.id_block: track ids reserved per write of the reservation, >= 1 (a crash skips at
  /// most this many ids).
  std::int64_t id_block = 100000;

  /// tracker: the algorithm options (config::ParseTrackerOptions's `tracker:` map).
  tracker::TrackerOptions tracker;

  /// The number of window-job workers to start: `workers`, or the core count when 0.
  int EffectiveWorkers() const;
};

/// Parses a daemon configuration; `source_name` (usually the path) is used in errors and
/// relative paths are resolved against `base_dir`. A non-empty `calibration_override` replaces
/// cameras.calibration (used as given, relative to the working directory; the daemon's
/// --calibration option).
/// @throws config::ConfigError on any syntax or content error, also for a missing or invalid
/// calibration file (the error names that file) and for ids absent from the calibration.
DaemonConfig ParseDaemonConfig(std::string_view text,
                               const std::string& source_name,
                               const std::string& base_dir,
                               const std::string& calibration_override = "");

/// Reads and parses the daemon configuration at `path` (relative names resolve against the
/// file's directory); `calibration_override` as in ParseDaemonConfig.
/// @throws config::ConfigError as ParseDaemonConfig, and when the file cannot be read.
DaemonConfig LoadDaemonConfigFile(const std::string& path,
                                  const std::string& calibration_override = "");

/// True when `text` looks like a daemon configuration: a YAML map with a `cameras` key or a
/// `format` starting with "mvtrack.daemon/" (so a wrong format version is reported by the
/// daemon validator). Used by `mvtrack check-config` to choose the validator. Never throws.
bool LooksLikeDaemonConfig(std::string_view text);

/// The effective configuration as a canonical YAML document (every key, fixed order, reals in
/// their shortest exact form, the calibration path as given resolved, and the tracker options
/// in full). Equal configurations give identical text.
std::string DaemonConfigToYaml(const DaemonConfig& config);

/// The LCM subscription queue capacity in use: input.lcm_queue_capacity, or when 0, 30 messages
/// per configured camera (one second of a 30 fps camera; LCM's own default is 30 in all).
int LcmQueueCapacity(const DaemonConfig& config);

/// 64-bit FNV-1a of DaemonConfigToYaml(config) and the canonical calibration text, as 16 hex
/// digits: identifies the configuration in status messages and logs.
std::string DaemonConfigHash(const DaemonConfig& config);

}  // namespace mvtrack::service
