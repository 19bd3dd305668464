#pragma once
/// @file
/// FrameSynchronizer: the daemon's input stage in front of the tracker. It groups camera-frames
/// into synchronized frames (by frame index, or by capture utime within a tolerance), rejects
/// camera-frames that break time order (time going backwards, duplicates, far-future
/// timestamps, late arrivals for a frame already released, flooding), excludes silent cameras
/// and re-includes them when they return, and releases each frame's camera-frames to the
/// tracker in frame order once every active camera has delivered or the late-camera deadline
/// has passed.
///
/// Every decision depends only on the sequence of camera-frame headers (camera id, frame
/// index, utime), never on the wall clock or on thread timing: the same input sequence always
/// produces the same releases.
///
/// Clock model (docs/DAEMON.md "Time"): the stream's time ("now") is the quorum's, the lower
/// median of the newest accepted utime (and, by frame index, frame index) of the cameras in
/// good standing (with data, not silent, clock not flagged), never one message's. Each camera's
/// offset to the quorum of the other cameras (at least two) is sampled on every camera-frame it
/// sends; the median of its last 16 samples (from 8 on) beyond SyncOptions::clock_tolerance_us
/// plus its own frame period (the others' newest frame may be a frame behind) or beyond
/// max_frame_offset frames flags its clock and rejects its camera-frames, alone, until the
/// median is back within half the tolerance (plus the period). A camera with
/// resync_after_rejections consecutive order rejections starts over alone; the whole stream
/// restarts when more than half of the cameras with data had kStreamVoteRejections consecutive
/// camera-frames rejected for their time, order or clock (a step of the whole rig's time: the
/// cameras then disagree with the old stream, not with each other), and every clock is judged
/// again in the new stream. All time and frame arithmetic saturates.
///
/// Single-owner, single-threaded object; deterministic; never throws on input. Memory is
/// bounded by SyncOptions::max_pending_frames frames of at most one camera-frame per camera.

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/detection.h"
#include "core/types.h"
#include "service/daemon_config.h"

namespace mvtrack::service {

/// Why the synchronizer refused a camera-frame.
enum class SyncRejection {
  kNone,           ///< accepted
  kUnknownCamera,  ///< the camera id is not configured
  kBackwards,      ///< utime (or, by frame index, the frame index) older than the camera's last
  kDuplicate,      ///< the camera already delivered this utime / frame index / frame
  kFarFuture,      ///< utime (or frame index) too far ahead of the newest accepted one
  kLate,           ///< its synchronized frame was already released
  kFlood,          ///< less than min_frame_interval_us after the camera's previous frame
  kClockOffset,    ///< the camera's clock (or frame counter) disagrees with the quorum's
};

/// "unknown camera", "time backwards", "duplicate", "far future", "late", "flood",
/// "clock offset".
const char* ToString(SyncRejection rejection);

/// One thing the caller must do, in order.
struct SyncAction {
  enum class Kind {
    kSubmit,     ///< hand `frame` to the tracker
    kEndStream,  ///< the stream restarted: end the tracker's stream (Pipeline::Flush) here
  };
  Kind kind = Kind::kSubmit;  ///< what to do
  core::CameraFrame frame;    ///< kSubmit: the camera-frame (frame index final)
};

/// A camera's exclusion or clock state changed (for logging and flags).
struct CameraTransition {
  enum class Kind {
    kSilence,  ///< `excluded`: became silent and is excluded; else re-included
    kClock,    ///< `excluded`: its clock was flagged (its frames are rejected); else cleared
    kRestart,  ///< the camera restarted alone (its own time order starts over)
  };
  CameraId camera_id = 0;  ///< the camera
  bool excluded = false;   ///< see Kind
  Kind kind = Kind::kSilence;
  std::int64_t offset_us = 0;      ///< kClock: the camera's offset to the quorum, µs
  std::int64_t offset_frames = 0;  ///< kClock, by frame index: its frame offset
};

/// The outcome of one Add().
struct SyncResult {
  SyncRejection rejection = SyncRejection::kNone;  ///< kNone when accepted
  std::string reason;                              ///< human-readable, when rejected
  /// True when this call detected a stream restart (see FrameSynchronizer); the
  /// actions then contain the release of every pending frame and a kEndStream, after which the
  /// camera-frame was accepted into a new stream.
  bool resynced = false;
  std::vector<SyncAction> actions;            ///< releases (and stream ends), in order
  std::vector<CameraTransition> transitions;  ///< exclusions and re-inclusions, in order
};

/// Per-camera state and counters.
struct SyncCameraStatus {
  CameraId camera_id = 0;  ///< the camera
  bool has_data = false;   ///< delivered an accepted camera-frame since start
  /// Silent: frames do not wait for it. A camera not yet seen is waited for until
  /// silent_after_us of capture time has passed since the stream's first camera-frame.
  bool excluded = false;
  Utime last_utime = 0;           ///< newest accepted capture utime (0 before any)
  std::int64_t accepted = 0;      ///< camera-frames accepted (and submitted, or pending)
  std::int64_t backwards = 0;     ///< rejected: time backwards
  std::int64_t duplicates = 0;    ///< rejected: duplicate
  std::int64_t far_future = 0;    ///< rejected: far future
  std::int64_t late = 0;          ///< rejected: frame already released
  std::int64_t flood = 0;         ///< dropped: flooding
  std::int64_t clock_offset = 0;  ///< rejected: clock (or frame counter) off the quorum's
  bool clock_flagged = false;     ///< its clock is flagged now (CLOCK_OFFSET)
  /// Median offset of its capture times to the quorum's, µs (0 before 8 samples).
  std::int64_t offset_us = 0;
  std::int64_t offset_frames = 0;  ///< by frame index: median frame offset
  std::int64_t restarts = 0;       ///< times it restarted alone
  /// Frames it never sent: gaps in its frame indices (frame_index mode), or steps of more than
  /// 1.5 of its frame periods in its capture times (utime mode), over accepted camera-frames.
  std::int64_t lost = 0;
  std::int64_t detections_rejected = 0;  ///< detections in this camera's rejected frames
  std::int64_t missed = 0;               ///< released frames this active camera did not deliver to
};

/// Global counters.
struct SyncStatus {
  std::vector<SyncCameraStatus> cameras;  ///< by ascending camera id
  std::int64_t unknown_camera = 0;        ///< camera-frames of unconfigured cameras
  std::int64_t frames_released = 0;       ///< synchronized frames released
  std::int64_t released_complete = 0;     ///< ... with every active camera
  std::int64_t released_by_deadline = 0;  ///< ... at the late-camera deadline
  std::int64_t released_by_bound = 0;     ///< ... because max_pending_frames was reached
  std::int64_t released_by_flush = 0;     ///< ... by Flush() or a resync
  std::int64_t resyncs = 0;               ///< stream restarts detected
  std::size_t pending_frames = 0;         ///< frames waiting now
};

/// The synchronizer; see the file comment.
class FrameSynchronizer {
 public:
  /// Consecutive camera-frames rejected for their time (backwards, late, far future or clock
  /// offset) that make a camera count as restarted in the stream restart vote (at most
  /// SyncOptions::resync_after_rejections, which alone restarts a single camera): as many as
  /// the clock flag needs samples, so a whole rig whose time stepped (an NTP step, a reboot
  /// with reset frame counters) restarts the stream within that many of its frames.
  static constexpr int kStreamVoteRejections = 8;
  /// ... or, for a slow camera, kStreamVoteMinRejections of them spanning this much of its own
  /// capture time, µs: at 2 fps 8 frames would take 4 s, 3 frames over 1 s restart within 1.5 s.
  static constexpr std::int64_t kStreamVoteSpanUs = 1'000'000;
  /// See kStreamVoteSpanUs.
  static constexpr int kStreamVoteMinRejections = 3;

  /// `camera_ids`: the configured cameras (any order, distinct); `options` valid (as parsed).
  FrameSynchronizer(std::vector<CameraId> camera_ids, const SyncOptions& options);

  /// Offers one decoded camera-frame. On acceptance it may release pending frames (actions).
  SyncResult Add(core::CameraFrame frame);

  /// End of input (or all cameras idle): releases every pending frame in order and forgets the
  /// stream's time position (per-camera order checks stay), so a later restart is accepted.
  std::vector<SyncAction> Flush();

  /// Counters and states.
  SyncStatus Status() const;
  /// The options in use.
  const SyncOptions& options() const { return options_; }

 private:
  static constexpr std::size_t kOffsetSamples = 16;
  static constexpr std::size_t kMinOffsetSamples = 8;
  struct Camera {
    SyncCameraStatus status;
    FrameIndex last_frame = 0;
    int order_rejections = 0;  // consecutive
    // Consecutive rejections for time (order rejections and clock offset): the stream restart
    // vote (a whole rig whose time stepped first gets its clocks flagged against the old time).
    int time_rejections = 0;
    // Capture time of the first and of the newest camera-frame of that run of rejections.
    Utime first_rejected_utime = 0;
    Utime last_rejected_utime = 0;
    // The other cameras' quorum utime when it last delivered (its own utime without one):
    // silence is judged on the others' clocks, so a camera ahead cannot silence the rest and a
    // dead one is noticed however few cameras there are.
    Utime quorum_at_last = 0;
    // The last kOffsetSamples offsets to the quorum (ring), µs and frames.
    std::array<std::int64_t, kOffsetSamples> offset_us{};
    std::array<std::int64_t, kOffsetSamples> offset_frames{};
    std::size_t num_offsets = 0;
    std::size_t next_offset = 0;
    // Its last accepted utime steps (ring): the median is its frame period, the slack of its
    // offset samples (the other cameras' newest frame may be one frame behind or ahead).
    std::array<std::int64_t, 8> steps{};
    std::size_t num_steps = 0;
    std::size_t next_step = 0;
  };
  struct Group {
    // The deadline counts from here: the stream's time when the frame last gained a member (the
    // first member's utime before the stream has a time), so no camera's clock, behind or
    // ahead, can release a frame before the others delivered to it.
    Utime reference_utime = 0;
    std::vector<std::optional<core::CameraFrame>> members;  // by camera index
  };

  SyncRejection Check(const core::CameraFrame& frame,
                      int camera_index,
                      std::string* reason,
                      std::int64_t* key) const;
  // Whether camera `c` counts as restarted in the stream restart vote (kStreamVoteRejections,
  // kStreamVoteSpanUs).
  bool OutOfStep(const Camera& c) const;
  // Whether camera `c` counts for the quorum (with data, not silent, clock not flagged).
  bool InQuorum(const Camera& c) const;
  // Lower median of the newest utime / frame of the quorum's cameras other than `skip` (-1:
  // none); nullopt with fewer than `min_cameras`.
  std::optional<std::pair<Utime, FrameIndex>> QuorumTime(int skip, std::size_t min_cameras) const;
  // Samples camera `index`'s offset to the others' quorum and updates its clock flag.
  void UpdateClock(const core::CameraFrame& frame, int index, SyncResult* result);
  // Recomputes now_utime_ / now_frame_ from the quorum.
  void UpdateNow();
  // The stream restarted: release everything, end the tracker's stream, forget time.
  void Resync(SyncResult* result);
  // Camera `camera_index` restarted alone: drops (and counts as far future) its pending
  // camera-frames ahead of the stream's time.
  void DropAhead(int camera_index);
  void Accept(core::CameraFrame frame, int camera_index, std::int64_t key, SyncResult* result);
  void Release(std::vector<SyncAction>* actions, bool force_all);
  void ReleaseOldest(std::vector<SyncAction>* actions);
  void UpdateExclusions(std::vector<CameraTransition>* transitions);

  SyncOptions options_;
  std::map<CameraId, int> index_of_;
  std::vector<Camera> cameras_;            // by ascending id
  std::map<std::int64_t, Group> pending_;  // key: frame index, or reference utime (kUtime)
  std::optional<std::int64_t> last_released_key_;
  // The stream's time: the quorum's newest utime and frame (see the file comment).
  std::optional<Utime> now_utime_;
  std::optional<FrameIndex> now_frame_;
  std::optional<Utime> stream_start_utime_;
  FrameIndex next_frame_index_ = 0;  // kUtime numbering
  SyncStatus counters_;
};

}  // namespace mvtrack::service
