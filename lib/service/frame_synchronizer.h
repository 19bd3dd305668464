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
/// produces the same releases. "Now" is the newest accepted capture utime.
///
/// Single-owner, single-threaded object; deterministic; never throws on input. Memory is
/// bounded by SyncOptions::max_pending_frames frames of at most one camera-frame per camera.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
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
};

/// "unknown camera", "time backwards", "duplicate", "far future", "late", "flood".
const char* ToString(SyncRejection rejection);

/// One thing the caller must do, in order.
struct SyncAction {
  enum class Kind {
    kSubmit,     ///< hand `frame` to the tracker
    kEndStream,  ///< the stream restarted: end the tracker's stream (Pipeline::Flush) here
  };
  Kind kind = Kind::kSubmit;            ///< what to do
  core::CameraFrame frame;              ///< kSubmit: the camera-frame (frame index final)
};

/// A camera's exclusion state changed (for logging and flags).
struct CameraTransition {
  CameraId camera_id = 0;  ///< the camera
  bool excluded = false;   ///< true: became silent and is excluded; false: re-included
};

/// The outcome of one Add().
struct SyncResult {
  SyncRejection rejection = SyncRejection::kNone;  ///< kNone when accepted
  std::string reason;                              ///< human-readable, when rejected
  /// True when this call detected a stream restart (resync_after_rejections reached); the
  /// actions then contain the release of every pending frame and a kEndStream, after which the
  /// camera-frame was accepted into a new stream.
  bool resynced = false;
  std::vector<SyncAction> actions;          ///< releases (and stream ends), in order
  std::vector<CameraTransition> transitions;  ///< exclusions and re-inclusions, in order
};

/// Per-camera state and counters.
struct SyncCameraStatus {
  CameraId camera_id = 0;        ///< the camera
  bool has_data = false;         ///< delivered an accepted camera-frame since start
  /// Silent: frames do not wait for it. A camera not yet seen is waited for until
  /// silent_after_us of capture time has passed since the stream's first camera-frame.
  bool excluded = false;
  Utime last_utime = 0;          ///< newest accepted capture utime (0 before any)
  std::int64_t accepted = 0;     ///< camera-frames accepted
  std::int64_t backwards = 0;    ///< rejected: time backwards
  std::int64_t duplicates = 0;   ///< rejected: duplicate
  std::int64_t far_future = 0;   ///< rejected: far future
  std::int64_t late = 0;         ///< rejected: frame already released
  std::int64_t flood = 0;        ///< dropped: flooding
  std::int64_t detections_rejected = 0;  ///< detections in this camera's rejected frames
  std::int64_t missed = 0;       ///< released frames this active camera did not deliver to
};

/// Global counters.
struct SyncStatus {
  std::vector<SyncCameraStatus> cameras;     ///< by ascending camera id
  std::int64_t unknown_camera = 0;           ///< camera-frames of unconfigured cameras
  std::int64_t frames_released = 0;          ///< synchronized frames released
  std::int64_t released_complete = 0;        ///< ... with every active camera
  std::int64_t released_by_deadline = 0;     ///< ... at the late-camera deadline
  std::int64_t released_by_bound = 0;        ///< ... because max_pending_frames was reached
  std::int64_t released_by_flush = 0;        ///< ... by Flush() or a resync
  std::int64_t resyncs = 0;                  ///< stream restarts detected
  std::size_t pending_frames = 0;            ///< frames waiting now
};

/// The synchronizer; see the file comment.
class FrameSynchronizer {
 public:
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
  struct Camera {
    SyncCameraStatus status;
    FrameIndex last_frame = 0;
  };
  struct Group {
    Utime utime_min = 0;
    std::vector<std::optional<core::CameraFrame>> members;  // by camera index
  };

  SyncRejection Check(const core::CameraFrame& frame, int camera_index, std::string* reason,
                      std::int64_t* key) const;
  void Accept(core::CameraFrame frame, int camera_index, std::int64_t key, SyncResult* result);
  void Release(std::vector<SyncAction>* actions, bool force_all);
  void ReleaseOldest(std::vector<SyncAction>* actions);
  void UpdateExclusions(std::vector<CameraTransition>* transitions);

  SyncOptions options_;
  std::map<CameraId, int> index_of_;
  std::vector<Camera> cameras_;  // by ascending id
  std::map<std::int64_t, Group> pending_;  // key: frame index, or reference utime (kUtime)
  std::optional<std::int64_t> last_released_key_;
  std::optional<Utime> newest_utime_;
  std::optional<FrameIndex> newest_frame_;
  std::optional<Utime> stream_start_utime_;
  FrameIndex next_frame_index_ = 0;  // kUtime numbering
  int consecutive_order_rejections_ = 0;
  SyncStatus counters_;
};

}  // namespace mvtrack::service
