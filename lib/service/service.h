#pragma once
/// @file
/// Service: the runtime of the daemon `mvtrackd`, everything but `main` (LCM wiring lives in
/// service/lcm_runner.h, signals and systemd in daemon/). It turns raw detection messages into
/// published tracks and status messages:
/// ```
///  OnMessage(channel, bytes)            control thread (the LCM receive loop)
///    safe decode (transport::DecodeCameraDetections), channel/camera check
///    FrameSynchronizer: order checks, grouping, silent cameras, deadline ──► releases
///    pipeline::Pipeline::Submit        one thread per camera, scheduler, worker pool, linker
///  finalizer thread: Frame3D ──► tracks3d_t (publish_utime, latency) ──► publish callback
///  Tick()                               control thread: status message every period, idle flush
/// ```
/// Decisions depend only on the messages (their order and their capture utimes): the wall clock
/// only stamps and measures (publish_utime, latency_us, status period), except the optional
/// idle flush after SyncOptions::idle_flush_s without any input. With lossless queues
/// (camera_overflow: block) the published tracks are therefore those `mvtrack replay` writes
/// for the same messages, whatever the number of workers.
///
/// Thread safety: OnMessage, Tick, EndOfInput, Reload, Stop, Counters and BuildStatus must be
/// called from one thread (the control thread); the finalizer thread only runs the frame
/// output, which shares its state with them under a mutex.
/// The publish callback is called from the control thread (status) and from the pipeline's
/// finalizer thread (tracks), never concurrently (the service serialises it).
///
/// Shutdown: Stop() ends the input, releases every pending frame, finishes the open windows,
/// publishes every remaining frame and a final status, flushes the record log and joins every
/// thread. Idempotent; also run by the destructor.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "analytics/site_analytics.h"
#include "core/keypoint_layout.h"
#include "pipeline/clock.h"
#include "pipeline/pipeline.h"
#include "service/daemon_config.h"
#include "service/frame_synchronizer.h"
#include "service/id_reservation.h"
#include "service/rate_limiter.h"
#include "tracker/types.h"

namespace mvtrack::transport {
class LogWriter;
}  // namespace mvtrack::transport

namespace mvtrack::service {

/// How the service talks to the outside world.
struct ServiceHooks {
  /// Publishes an encoded message (tracks3d_t on the tracks channel, tracker_status_t on the
  /// status channel). May be empty (no LCM output). Must not throw.
  std::function<void(const std::string& channel, const std::vector<std::uint8_t>& data)> publish;
  /// Also receives every published frame with its track ids as published (for --tracks-jsonl);
  /// called on the finalizer thread. May be empty.
  std::function<void(const tracker::Frame3D& frame, core::KeypointLayoutId layout)> on_frame;
  /// Likewise for every published provisional frame (output.provisional_channel). May be empty.
  std::function<void(const tracker::Frame3D& frame, core::KeypointLayoutId layout)> on_provisional;
  /// Wall clock, µs since the Unix epoch (publish_utime, receive times, status period). Null:
  /// an internal pipeline::SystemClock. Must outlive the service.
  const pipeline::Clock* wall_clock = nullptr;
  /// When not empty, every received message and every published message is written to this LCM
  /// log (input on its own channel with the receive time as event time; outputs with their
  /// publish_utime), so an incident can be replayed with `mvtrack replay`.
  std::string record_path;
  /// The daemon's version string for tracker_status_t.version.
  std::string version = "unknown";
  /// The datagrams the kernel dropped for the input's sockets (full receive buffer), cumulative,
  /// e.g. ProcessUdpDrops for a udpm:// input; nullopt when unknown. Called at each status and
  /// by Counters(), never per message. Empty: not measured (tracker_status_t.kernel_drops -1).
  std::function<std::optional<std::int64_t>()> kernel_drops;
};

/// Cumulative counters of the service (for the exit summary, tests and the status message).
struct ServiceCounters {
  std::int64_t messages = 0;          ///< messages handed to OnMessage
  std::int64_t foreign_messages = 0;  ///< not on a detections channel
  std::int64_t decode_errors = 0;     ///< detections messages that failed to decode
  std::map<std::string, std::int64_t> decode_errors_by_kind;  ///< by DecodeStatus name
  std::int64_t channel_mismatches = 0;     ///< camera id differs from a per-camera channel
  std::int64_t image_size_mismatches = 0;  ///< image size differs from the calibration
  std::int64_t camera_frames_decoded = 0;  ///< decoded camera-frames given to the synchronizer
  std::int64_t sync_rejected = 0;          ///< refused by the synchronizer (any reason)
  std::map<std::string, std::int64_t> sync_rejections;  ///< by SyncRejection name
  std::int64_t submitted = 0;                           ///< camera-frames submitted to the pipeline
  std::int64_t gate_rejected = 0;                       ///< rejected by the tracker's FrameGate
  std::int64_t frames_published = 0;                    ///< tracks messages published
  std::int64_t provisional_published = 0;               ///< provisional tracks messages published
  std::int64_t analytics_events_published = 0;          ///< analytics_event_t published
  std::int64_t site_counts_published = 0;               ///< site_counts_t published
  std::int64_t status_published = 0;                    ///< status messages published
  std::int64_t idle_flushes = 0;                        ///< idle flushes (all cameras silent)
  std::int64_t stream_restarts = 0;                     ///< synchronizer resyncs
  std::int64_t reloads = 0;                             ///< successful configuration reloads
  std::int64_t record_errors = 0;   ///< record-log write failures (recording then stops)
  std::int64_t log_suppressed = 0;  ///< warnings suppressed by rate limiting
  std::int64_t max_latency_us = 0;  ///< largest processing latency_us published
  /// Receive-to-publish latency of the frames published in steady state, µs, in publish order
  /// (at most kMaxReceiveLatencySamples, the first ones): publish time minus the time the
  /// frame's first camera-frame was received (frame_index mode; in utime mode, minus its
  /// release time). Capture-to-publish when the cameras publish at capture time (a live feed,
  /// or a log played in real time). Frames output by a flush (end of input, idle flush,
  /// reload, stream restart, stop) are not sampled: their wait is the input's silence.
  std::vector<std::int64_t> receive_to_publish_us;
  /// The same for the provisional layer (output.provisional_channel), µs.
  std::vector<std::int64_t> provisional_receive_to_publish_us;
  std::int64_t frames_published_by_flush = 0;  ///< frames published during a flush
  /// Input datagrams the kernel dropped (ServiceHooks::kernel_drops); -1 when not measured.
  std::int64_t kernel_drops = -1;
  SyncStatus sync;                    ///< synchronizer counters
  pipeline::PipelineStatus pipeline;  ///< pipeline counters (current pipeline)
};

/// Bound on ServiceCounters::receive_to_publish_us (8 MB).
inline constexpr std::size_t kMaxReceiveLatencySamples = 1000000;

/// The daemon runtime; see the file comment.
class Service {
 public:
  /// Builds the rig, the synchronizer and the pipeline and opens the record log. Returns
  /// nullptr and sets `why` on failure (invalid rig or options, record log not writable).
  static std::unique_ptr<Service> Create(DaemonConfig config, ServiceHooks hooks, std::string* why);
  /// Stop()s.
  ~Service();
  Service(const Service&) = delete;
  Service& operator=(const Service&) = delete;

  /// One raw LCM message (any channel). Never throws; bad input is counted and logged with
  /// rate limiting. With camera_overflow: block it may wait for room in a camera queue.
  void OnMessage(const std::string& channel, const std::uint8_t* data, std::size_t size);

  /// Periodic housekeeping (call often, e.g. every 50 ms): publishes the status message when
  /// its period has passed and performs the idle flush when due.
  void Tick();

  /// End of input (end of a log): releases every pending frame, finishes the open windows and
  /// waits until every frame has been published. Input may follow (a new stream).
  void EndOfInput();

  /// Applies a new configuration: the log level, the warning interval, the status period and
  /// the tracker options (the current stream is ended and a new pipeline started; published
  /// track ids keep increasing). Other changes need a restart and are reported in `why` (the
  /// reload still succeeds for the reloadable parts). Returns false, changing nothing, when
  /// the new tracker options do not build a pipeline.
  bool Reload(const DaemonConfig& config, std::string* why);

  /// Drains and stops; see the file comment.
  void Stop();

  /// A snapshot of the counters (control thread).
  ServiceCounters Counters() const;

  /// Builds (without publishing) an encoded tracker_status_t for the period since the previous
  /// status, and starts a new period (control thread).
  std::vector<std::uint8_t> BuildStatus();

  /// The configuration in use.
  const DaemonConfig& config() const { return config_; }
  /// DaemonConfigHash of the configuration in use.
  const std::string& config_hash() const { return config_hash_; }

 private:
  // Calls hooks_.kernel_drops and keeps the largest value; -1 while not measured.
  std::int64_t KernelDrops() const;

  struct CameraInput {
    std::int64_t received = 0;       // decoded messages
    std::int64_t decode_errors = 0;  // on this camera's channel
    std::int64_t received_at_period_start = 0;
    std::int64_t late_at_period_start = 0;
    std::int64_t dropped_at_period_start = 0;
    std::int64_t rejected_at_period_start = 0;
    std::int64_t decode_errors_at_period_start = 0;
    std::int64_t lost_at_period_start = 0;
    std::int64_t embeddings_dropped_at_period_start = 0;
    // This camera's counts in earlier pipelines (reloads), which start from 0.
    std::int64_t rejected_before = 0;
    std::int64_t embeddings_dropped_before = 0;
    std::int64_t last_receive_us = 0;
    std::int64_t last_utime = 0;
  };

  Service(DaemonConfig config, ServiceHooks hooks);
  std::unique_ptr<pipeline::Pipeline> MakePipeline(const tracker::TrackerOptions& options,
                                                   std::string* why);
  void Apply(std::vector<SyncAction>* actions);
  // pipeline_->Flush() with flushing_ set (frames it outputs are not latency-sampled).
  void FlushPipeline();
  void OnFrame(tracker::Frame3D frame);
  void OnProvisional(tracker::Frame3D frame);
  std::int64_t StampOutput(tracker::Frame3D* frame,
                           std::int64_t now,
                           bool final,
                           std::vector<std::int64_t>* samples);
  // Extends the id reservation (if needed) to cover every id of `frame` before it is published.
  void CoverIds(const tracker::Frame3D& frame);
  // The site analytics of a published frame: its events, and the counts when one changed.
  void Analyse(const tracker::Frame3D& frame, std::int64_t now);
  // Publishes site_counts_t (analytics_mu_ held).
  void PublishSiteCounts(std::int64_t now);
  void Publish(const std::string& channel,
               const std::vector<std::uint8_t>& data,
               std::int64_t time_us);
  void Record(const std::string& channel,
              const std::uint8_t* data,
              std::size_t size,
              std::int64_t time_us);
  void Warn(const std::string& kind, const std::string& message);
  std::int64_t Now() const { return wall_clock_->NowMicros(); }

  DaemonConfig config_;
  const ServiceHooks hooks_;
  std::string config_hash_;
  pipeline::SystemClock system_clock_;
  const pipeline::Clock* wall_clock_;
  pipeline::SteadyClock steady_clock_;
  const std::int64_t start_us_;
  const std::string instance_id_;  // tracker_status_t.instance_id
  core::KeypointLayoutId output_layout_ = core::KeypointLayoutId::kNone;

  // Control thread only.
  FrameSynchronizer sync_;
  std::unique_ptr<pipeline::Pipeline> pipeline_;
  std::map<CameraId, int> camera_index_;
  std::int64_t last_message_us_ = 0;
  // Start of the current run of input without a kNoOutputAfterUs pause (NO_OUTPUT is judged
  // from here or from the last publish, whichever is later).
  std::int64_t input_since_us_ = 0;
  bool any_message_ = false;
  bool idle_flushed_ = true;
  std::int64_t next_status_us_ = 0;
  std::int64_t period_start_us_ = 0;
  std::int64_t status_sequence_ = 0;  // tracker_status_t.sequence of the next status (under mu_)
  bool stopped_ = false;

  RateLimiter limiter_;

  // Shared between the control and the finalizer thread (guarded by mu_).
  mutable std::mutex mu_;
  ServiceCounters counters_;
  std::vector<CameraInput> inputs_;                      // by camera index
  std::map<FrameIndex, std::int64_t> release_us_;        // frame -> wall time of its last release
  std::map<FrameIndex, std::int64_t> first_receive_us_;  // frame -> first camera-frame received
  std::vector<std::int64_t> latency_samples_;            // latency_us published this period
  TrackId3D id_offset_ = 0;                              // added to pipeline ids (reloads)
  TrackId3D max_published_id_ = 0;
  FrameIndex last_frame_ = -1;
  std::int64_t last_publish_us_ = 0;  // wall time of the newest published frame (0: none)
  int active_tracks_ = 0;
  int confirmed_tracks_ = 0;
  std::int64_t windows_before_ = 0;  // windows processed by earlier pipelines (reloads)
  std::int64_t jobs_failed_before_ = 0;
  std::int64_t embeddings_used_before_ = 0;
  std::int64_t embeddings_dropped_before_ = 0;
  std::int64_t tracks_revived_before_ = 0;
  std::int64_t jobs_failed_at_period_start_ = 0;
  // Largest value hooks_.kernel_drops returned (it never decreases, even if a socket closed);
  // -1 while never measured.
  mutable std::atomic<std::int64_t> kernel_drops_{-1};
  std::int64_t kernel_drops_at_period_start_ = 0;

  // The site analytics (config_.site_path; none when empty), fed by the finalizer thread,
  // its counts also published by the control thread with each status (guarded by
  // analytics_mu_).
  std::optional<analytics::SiteAnalytics> analytics_;
  std::int64_t analytics_utime_ = 0;  // capture time of the newest frame analysed
  std::mutex analytics_mu_;

  // Set while the control thread flushes the pipeline (read by the finalizer thread).
  std::atomic<bool> flushing_{false};

  // Track ids above every earlier run's (config_.state_directory; none when empty). The
  // finalizer thread extends it itself when a published id reaches its end (guarded by
  // reservation_mu_; reserved_end_ mirrors reservation_.reserved_end(), max when unused).
  std::optional<IdReservation> reservation_;
  std::mutex reservation_mu_;
  std::atomic<TrackId3D> reserved_end_{std::numeric_limits<TrackId3D>::max()};
  bool ExtendReservation(TrackId3D next_id, std::string* why);

  // Serialises publish callbacks and record writes.
  std::mutex out_mu_;
  std::unique_ptr<transport::LogWriter> record_;
};

}  // namespace mvtrack::service
