#pragma once
/// @file
/// WindowBuilder: the sliding-window stage (paper Sec. "Method", sliding window ν, δ). It
/// collects the TrackedCameraFrames of every camera, closes frames, decides which windows are
/// complete on the window grid, and emits one immutable WindowJob per window — together with
/// the closed-frame records and end-of-stream markers the WindowFinalizer needs — as one
/// ordered output sequence. Pure, single-owner, single-threaded object.

#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <utility>
#include <variant>
#include <vector>

#include "core/observation.h"
#include "core/types.h"
#include "geometry/camera_rig.h"
#include "tracker/camera_stage.h"
#include "tracker/frame_gate.h"
#include "tracker/frame_period.h"
#include "tracker/options.h"
#include "tracker/provisional.h"
#include "tracker/window_job.h"

namespace mvtrack::tracker {

/// A frame was closed: it will be finalized (output) by exactly one later window or stream end.
struct ClosedFrame {
  FrameIndex frame = 0;  ///< the closed frame
  Utime utime = 0;       ///< the smallest utime among its camera-frames
  /// Every camera's observations of its 2D tracks in this frame (for the provisional layer,
  /// ProvisionalEstimator); empty unless the builder was made with keep_frame_views.
  std::vector<FrameView> views;
};

/// The stream ended (re-anchor or flush): every closed frame not yet output is final now.
struct StreamEnd {};

/// One element of the WindowBuilder's output sequence. The consumer must apply them in order
/// (WindowFinalizer: AddClosedFrame, Finalize(ProcessWindowJob(job)), EndStream); only the
/// WindowJobs' processing may happen out of order or in parallel.
using BuilderOutput = std::variant<ClosedFrame, WindowJob, StreamEnd>;

/// Window grid (docs/DECISIONS.md "Tracker facade"): window k covers [F0 + kδ, F0 + kδ + ν),
/// with ν, δ (and the minimum tracklet length) of AtFrameRate(options, SecondsPerFrame()) fixed
/// per stream once three of its frames are closed (or at its end), so a 2 fps stream gets
/// windows as long in seconds as a 25 fps one; until then no window is emitted;
/// F0 = the multiple of δ at or before the first frame of the stream (a tracker of the same
/// camera stream that started later, e.g. another zone of a site, has the same windows). A
/// window is emitted once its last frame is closed or, for
/// frames skipped in the input, once a later frame opens. Window k finalizes
/// [F0 + kδ + ⌊(ν−δ)/2⌋, F0 + kδ + ⌊(ν−δ)/2⌋ + δ) (window 0 from F0). At the end of a stream
/// (re-anchor or Flush) every window that begins at or before the last closed frame is emitted,
/// shortened to end after it, and the last one finalizes the tail. Window ids continue across
/// streams (the StreamEnd before them makes the finalizer end every track). Observations
/// that no later window needs are dropped after each window.
///
/// Single-owner, single-threaded; deterministic: the output depends only on the sequence of
/// calls.
class WindowBuilder {
 public:
  /// `options` must be valid (checked by the caller: Tracker::Create / Pipeline::Create).
  /// `keep_frame_views`: every ClosedFrame carries its frame's observations (ClosedFrame::views).
  WindowBuilder(const geometry::CameraRig& rig,
                const TrackerOptions& options,
                bool keep_frame_views = false);

  /// Applies one admitted camera-frame: first the frame-sequence `events` the FrameGate decided
  /// for it (close the open frame, re-anchor, open its frame), emitting whatever they complete,
  /// then stores `frame`'s observations, then closes the frame when the gate said so
  /// (FrameEvents::close_after). Calls must follow the gate's admission order, and
  /// `frame` must be the admitted camera-frame's output (checked for consistency with the
  /// events). Appends to `out`.
  void Add(const FrameEvents& events, TrackedCameraFrame frame, std::vector<BuilderOutput>* out);

  /// End of stream (Tracker::Flush; the FrameGate's Flush must be called for the same point of
  /// the sequence): closes the open frame, emits the remaining (partial) windows and a
  /// StreamEnd, and starts over with a new window grid. Does nothing without a stream.
  void Flush(std::vector<BuilderOutput>* out);

  /// The frame being collected, if any.
  const std::optional<FrameIndex>& open_frame() const { return open_frame_; }
  /// Number of stored 2D observations (all cameras, all live tracks).
  std::size_t num_stored_observations() const;
  /// The stream's frame period, measured from the capture times (utime) of its latest closed
  /// frames (FramePeriod: each frame's smallest camera utime). Every WindowJob carries it.
  double SecondsPerFrame() const { return period_.Seconds(); }
  /// The window length ν in effect (the options' until the stream's geometry is fixed).
  std::int64_t window_size() const { return window_size_; }

 private:
  struct TimedObservation {
    FrameIndex frame;
    core::Observation2D observation;
  };

  void CloseOpenFrame(std::vector<BuilderOutput>* out);
  void EmitWindowsUpTo(FrameIndex complete_through, bool flushing, std::vector<BuilderOutput>* out);
  void EmitWindow(std::int64_t window_id,
                  FrameIndex begin,
                  FrameIndex end,
                  FrameIndex finalize_from,
                  FrameIndex finalize_to,
                  std::vector<BuilderOutput>* out);
  void EndStream(std::vector<BuilderOutput>* out);
  void RememberClosed(FrameIndex frame, Utime utime);

  // Fixes ν, δ and the minimum tracklet length of this stream from its measured rate.
  void FixGeometry();

  std::vector<CameraId> camera_ids_;  // by rig index
  TrackerOptions options_;            // as given; the geometry below is AtFrameRate's
  bool geometry_fixed_ = false;
  std::int64_t window_size_ = 0;  // ν
  std::int64_t window_step_ = 0;  // δ
  int min_tracklet_length_ = 0;

  // Frame being collected.
  std::optional<FrameIndex> open_frame_;
  Utime open_utime_ = 0;
  bool keep_frame_views_ = false;
  std::vector<FrameView> open_views_;  // keep_frame_views_: the open frame's observations

  // Window grid.
  std::optional<FrameIndex> grid_origin_;  // the stream's first frame, then F0 (FixGeometry)
  std::int64_t window_id_offset_ = 0;      // added to grid window indices (re-anchoring)
  std::int64_t next_window_ = 0;           // grid index of the next window to emit
  std::optional<FrameIndex> last_closed_frame_;
  // The latest closed frames of the stream, for SecondsPerFrame.
  FramePeriod period_;

  /// By rig index: the observations of each 2D track, oldest first.
  std::vector<std::map<TrackId2D, std::vector<TimedObservation>>> tracks_;
};

}  // namespace mvtrack::tracker
