#pragma once
/// @file
/// Pipeline: the threaded composition of the tracker stages for the real-time daemon. It runs
/// exactly the stage code of tracker::Tracker (FrameGate, CameraStage, WindowBuilder,
/// ProcessWindowJob, WindowFinalizer) and, without overflow drops, its output is bit-identical
/// to the Tracker's on the same input sequence, whatever the number of workers.
///
/// Threads and data flow:
/// ```
///  Submit (caller thread, e.g. the LCM receive thread)
///    FrameGate: admit or reject (headers only), frame events, stream epoch, sequence number
///    ──► CameraQueue[c] (bounded; overflow policy)            one per camera
///  camera threads (camera c on thread c mod n): CameraStage c (validation, observations, SORT),
///    each thread taking the oldest (lowest sequence number) of its cameras' waiting items
///    ──► SequenceReorderBuffer (by sequence number)            look-ahead bounded
///  scheduler thread: WindowBuilder, consuming camera outputs in INPUT SEQUENCE ORDER
///    ├─ WindowJob ──► Executor (InlineExecutor / ThreadPoolExecutor workers):
///    │                ProcessWindowJob (association + CMMT), one workspace per worker
///    │                ──► results keyed by window_id (reorder buffer)
///    └─ steps (closed frames, windows, stream ends) ──► BoundedQueue
///  finalizer thread: WindowFinalizer, applying steps in order and waiting for each window's
///    result by window_id ──► output callback (finalized Frame3D, in frame order)
/// ```
///
/// Input order contract: camera-frames enter through Submit in one sequence (as LCM delivers
/// them on one thread; concurrent Submit calls are serialised, and their order is the input
/// order). Admission and every frame-sequencing decision are made in that order by the FrameGate
/// on the submitting thread, from headers only. Each accepted camera-frame gets the next
/// sequence number; camera threads may run ahead of each other, but the scheduler consumes their
/// outputs strictly by sequence number, and the finalizer links windows strictly by window_id,
/// so no decision and no output depends on thread timing. Time is only measured (Clock), never
/// used to decide.
///
/// Queues and policies:
///  - camera queues: PipelineOptions::camera_queue_capacity camera-frames with detections each;
///    overflow per PipelineOptions::camera_overflow (kDropOldest: Submit never blocks, the
///    oldest waiting camera-frame loses its detections and is counted; kBlock: Submit waits).
///  - reorder buffer: a camera thread more than reorder_capacity sequence numbers ahead of the
///    scheduler waits (then its queue fills and overflows as above).
///  - executor: ThreadPoolExecutor blocks the scheduler when its job queue is full.
///  - finalizer steps: the scheduler waits when finalizer_queue_capacity steps are pending.
/// Back-pressure therefore flows from a slow finalizer or executor to the camera queues, where
/// the overflow policy applies; memory is bounded (dropped camera-frames keep only a header).
///
/// Thread safety: Submit, Flush, Stop and Status may be called from any threads. The output
/// callback runs on the finalizer thread, one frame at a time, and must not call Submit, Flush
/// or Stop (deadlock; Flush and Stop check). Exceptions thrown by the callback are caught and
/// counted; a window job that throws becomes a failed window (counted, it links as a window without
/// persons) — no exception leaves a pipeline thread.
///
/// Shutdown: Stop() (also run by the destructor) refuses further input, then drains: every
/// accepted camera-frame is processed, open windows are finished and flushed exactly as
/// Tracker::Flush, every job completes, every finalized frame is delivered to the callback,
/// and all threads are joined before it returns.

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/detection.h"
#include "core/types.h"
#include "geometry/camera_rig.h"
#include "pipeline/bounded_queue.h"
#include "pipeline/camera_queue.h"
#include "pipeline/clock.h"
#include "pipeline/executor.h"
#include "pipeline/reorder_buffer.h"
#include "tracker/camera_stage.h"
#include "tracker/frame_gate.h"
#include "tracker/options.h"
#include "tracker/provisional.h"
#include "tracker/tracker.h"
#include "tracker/types.h"
#include "tracker/window_builder.h"
#include "tracker/window_finalizer.h"
#include "tracker/window_job.h"

namespace mvtrack::pipeline {

/// Queue sizes and policies of a Pipeline (see the file comment).
struct PipelineOptions {
  /// Camera-frames with detections waiting per camera thread, >= 1.
  int camera_queue_capacity = 8;
  /// What Submit does when a camera queue is full. kDropOldest for live use (the receiving
  /// thread never blocks; latency stays bounded), kBlock for replay and tests (lossless, so the
  /// output is bit-identical to tracker::Tracker).
  OverflowPolicy camera_overflow = OverflowPolicy::kDropOldest;
  /// How far (in sequence numbers) camera outputs may run ahead of the scheduler, >= 1.
  int reorder_capacity = 256;
  /// Steps (closed frames, windows, stream ends) pending for the finalizer thread, >= 1.
  int finalizer_queue_capacity = 1024;
  /// Threads running the camera stages, each serving a fixed share of the cameras (camera c on
  /// thread c mod n, its camera-frames in input order); 0 = one per hardware thread, at most one
  /// per camera. One thread per camera woke every camera's thread for every frame: at 32 cameras
  /// 38 context switches per frame (docs/BENCHMARKS.md "More threads, not slower"). >= 0.
  int camera_threads = 0;

  /// Checks the ranges above; on failure writes a reason naming the field to `why` (if not
  /// null).
  bool Validate(std::string* why) const;
};

/// Outcome of Submit.
enum class SubmitStatus {
  kAccepted,  ///< queued for its camera thread
  kRejected,  ///< rejected by the FrameGate (see SubmitResult::rejection)
  kStopped,   ///< the pipeline is stopping or stopped: nothing was done
};

/// What happened to one Submit call (the detection counters come later, from the camera
/// thread; see PipelineStatus).
struct SubmitResult {
  SubmitStatus status = SubmitStatus::kAccepted;  ///< accepted, rejected or stopped
  tracker::FrameRejection rejection = tracker::FrameRejection::kNone;  ///< kRejected: why
  std::string reason;     ///< kRejected: human-readable reason
  std::uint64_t seq = 0;  ///< kAccepted: the camera-frame's position in the input sequence
};

/// Window latency: from the window's job being built (its last frame closed) to its result
/// being linked and its frames handed to the callback, measured with the pipeline's Clock.
struct LatencyStats {
  std::int64_t count = 0;    ///< windows measured
  std::int64_t last_us = 0;  ///< latest window, µs
  std::int64_t max_us = 0;   ///< maximum, µs
  std::int64_t sum_us = 0;   ///< sum over the measured windows, µs
  /// Mean over the measured windows, µs (0 without any).
  double mean_us() const {
    return count > 0 ? static_cast<double>(sum_us) / static_cast<double>(count) : 0.0;
  }
};

/// Per-camera counters and queue depth.
struct CameraStatus {
  CameraId camera_id = 0;                ///< the camera
  std::size_t queue_depth = 0;           ///< camera-frames waiting (dropped headers included)
  std::int64_t frames_processed = 0;     ///< camera-frames run through the CameraStage
  std::int64_t frames_dropped = 0;       ///< camera-frames whose detections overflow discarded
  std::int64_t detections_rejected = 0;  ///< this camera's detections that failed validation
  std::int64_t embeddings_dropped = 0;   ///< this camera's unusable embeddings (appearance on)
};

/// A snapshot of the pipeline's counters and queue depths (for the daemon's status message).
struct PipelineStatus {
  /// The Tracker's counters, with the same meaning (detections of dropped camera-frames are
  /// not counted). Without drops, equal to Tracker::stats() after the same input.
  tracker::TrackerStats tracker;
  std::vector<CameraStatus> cameras;        ///< rig order
  std::int64_t camera_frames_dropped = 0;   ///< sum over cameras
  std::size_t reorder_depth = 0;            ///< camera outputs waiting for the scheduler
  std::size_t finalizer_queue_depth = 0;    ///< steps waiting for the finalizer thread
  std::size_t results_waiting = 0;          ///< finished windows waiting for an earlier one
  std::int64_t windows_submitted = 0;       ///< jobs handed to the executor
  std::int64_t windows_failed = 0;          ///< jobs that threw (linked as empty windows)
  std::string last_failure;                 ///< the latest failed job's error
  std::int64_t output_callback_errors = 0;  ///< exceptions thrown by the output callback
  LatencyStats window_latency;              ///< see LatencyStats
  ExecutorStats executor;                   ///< the executor's counters and queue depth
  /// The id the next new track will get (every id below it may have been given out; the
  /// daemon's id reservation covers it before it is published).
  TrackId3D next_track_id = 1;
};

/// The threaded tracker; see the file comment.
class Pipeline {
 public:
  /// Receives each finalized frame, in increasing frame order, on the finalizer thread.
  using FrameCallback = std::function<void(tracker::Frame3D frame)>;

  /// Builds and starts the pipeline (one thread per camera, a scheduler and a finalizer
  /// thread). Returns nullptr and sets `why` when `options` or `pipeline_options` are invalid,
  /// the rig has fewer than two cameras, `executor` is null or `on_frame` is empty. `clock`
  /// must outlive the pipeline. The executor is owned and stopped by the pipeline.
  /// `on_provisional` (optional) receives the provisional frame of every closed frame
  /// (tracker::ProvisionalEstimator), on the finalizer thread, as soon as the windows before it
  /// are linked: the same frames, bit for bit, as tracker::Tracker::TakeProvisional.
  static std::unique_ptr<Pipeline> Create(geometry::CameraRig rig,
                                          tracker::TrackerOptions options,
                                          PipelineOptions pipeline_options,
                                          std::unique_ptr<Executor> executor,
                                          const Clock& clock,
                                          FrameCallback on_frame,
                                          std::string* why,
                                          FrameCallback on_provisional = {});

  /// Stop()s.
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  /// Admits one camera-frame (FrameGate, on the calling thread) and queues it for its camera
  /// thread. With OverflowPolicy::kBlock it may wait for room; with kDropOldest it never
  /// blocks. Never throws on input.
  SubmitResult Submit(core::CameraFrame frame);

  /// End of stream at this point of the input sequence, as Tracker::Flush: closes the open
  /// frame, finishes the remaining windows and outputs every frame not yet output. Blocks until
  /// those frames have been handed to the callback. The pipeline accepts input afterwards (a
  /// new window grid starts; track ids keep increasing). Returns false if stopped.
  bool Flush();

  /// Drains and stops (see the file comment). Idempotent; thread-safe.
  void Stop();

  /// A snapshot of counters and queue depths; thread-safe, never blocks on the stages' work.
  PipelineStatus Status() const;

  /// The window latencies (see LatencyStats), µs, of the windows linked since the previous
  /// call, oldest first; at most kMaxLatencySamples are kept (older ones are discarded).
  /// Thread-safe (the daemon computes per-period percentiles from them).
  std::vector<std::int64_t> TakeWindowLatencies();
  /// Bound on the samples TakeWindowLatencies() keeps between calls.
  static constexpr std::size_t kMaxLatencySamples = 4096;

  /// The camera rig in use.
  const geometry::CameraRig& rig() const { return rig_; }
  /// The tracking options in use.
  const tracker::TrackerOptions& options() const { return options_; }
  /// The queue options in use.
  const PipelineOptions& pipeline_options() const { return pipeline_options_; }

 private:
  // One camera output (or a control item) in input-sequence order.
  struct SequencedItem {
    enum class Kind { kCameraFrame, kFlush, kStop };
    Kind kind = Kind::kCameraFrame;
    tracker::FrameEvents events;
    tracker::TrackedCameraFrame frame;
    std::uint64_t flush_ticket = 0;
  };
  // One step of the finalizer, in the WindowBuilder's output order.
  struct Step {
    enum class Kind { kClosedFrame, kWindow, kStreamEnd, kFlushDone, kStop };
    Kind kind = Kind::kClosedFrame;
    tracker::ClosedFrame closed;
    std::int64_t window_id = 0;
    std::int64_t close_time_us = 0;
    std::uint64_t flush_ticket = 0;
  };
  // A window whose job has run (or failed).
  struct FinishedWindow {
    tracker::WindowResult result;
    bool failed = false;
    std::string error;
  };
  // Per-camera counters (guarded by status_mu_).
  struct CameraCounters {
    std::int64_t frames_processed = 0;
    std::int64_t detections_rejected = 0;
    std::int64_t embeddings_dropped = 0;
  };

  Pipeline(geometry::CameraRig rig,
           tracker::TrackerOptions options,
           PipelineOptions pipeline_options,
           std::unique_ptr<Executor> executor,
           const Clock& clock,
           FrameCallback on_frame,
           FrameCallback on_provisional);
  void Start();
  void CameraWorkerLoop(int worker);
  void ProcessCameraWork(int camera_index, CameraWork work);
  void SchedulerLoop();
  void DispatchOutput(tracker::BuilderOutput* output);
  void FinishWindow(const tracker::WindowJob& job,
                    tracker::WindowResult result,
                    const JobOutcome& outcome);
  void FinalizerLoop();
  void Emit(std::vector<tracker::Frame3D>* frames);
  void EmitProvisional(tracker::Frame3D frame);

  // Immutable after construction (read by every thread).
  const geometry::CameraRig rig_;
  const tracker::TrackerOptions options_;
  const PipelineOptions pipeline_options_;
  const Clock& clock_;
  const FrameCallback on_frame_;
  const FrameCallback on_provisional_;  // may be empty
  const std::unique_ptr<Executor> executor_;

  // Input side (guarded by input_mu_).
  std::mutex input_mu_;
  tracker::FrameGate gate_;
  std::uint64_t next_seq_ = 0;
  std::uint64_t flush_requested_ = 0;
  bool stopping_ = false;

  // Camera threads: stage c and queue c are used by camera thread c only (queues are shared
  // with Submit).
  std::vector<std::unique_ptr<CameraQueue>> camera_queues_;
  std::vector<std::unique_ptr<WorkSignal>> camera_signals_;  // one per camera thread
  std::vector<std::unique_ptr<tracker::CameraStage>> stages_;
  SequenceReorderBuffer<SequencedItem> reorder_;

  // Scheduler thread only.
  tracker::WindowBuilder builder_;

  // Workers: workspace w is used only by the job running on worker w.
  std::vector<tracker::WindowWorkspace> workspaces_;

  // Scheduler -> finalizer.
  BoundedQueue<Step> steps_;
  mutable std::mutex results_mu_;
  std::condition_variable results_cv_;
  std::map<std::int64_t, FinishedWindow> results_;  // keyed by window_id

  // Finalizer thread only.
  tracker::WindowFinalizer finalizer_;
  std::optional<tracker::ProvisionalEstimator> provisional_;  // with on_provisional_

  // Flush completion (guarded by flush_mu_).
  std::mutex flush_mu_;
  std::condition_variable flush_cv_;
  std::uint64_t flush_done_ = 0;

  // Counters (guarded by status_mu_).
  mutable std::mutex status_mu_;
  tracker::TrackerStats stats_;
  std::vector<CameraCounters> camera_counters_;
  tracker::GalleryMemory gallery_memory_;
  std::int64_t windows_submitted_ = 0;
  std::int64_t windows_failed_ = 0;
  TrackId3D next_track_id_ = 1;  // guarded by status_mu_
  std::string last_failure_;
  std::int64_t output_callback_errors_ = 0;
  LatencyStats latency_;
  std::vector<std::int64_t> latency_samples_;  // since the last TakeWindowLatencies()

  // Threads and their shutdown.
  std::mutex stop_mu_;
  bool stopped_ = false;
  std::vector<std::thread> camera_threads_;
  std::thread scheduler_thread_;
  std::thread finalizer_thread_;
  std::thread::id finalizer_thread_id_;  // set by Start(), then read-only
};

}  // namespace mvtrack::pipeline
