#pragma once
/// @file
/// FrameGate: the admission and frame-sequencing stage. It decides, from camera-frame headers
/// alone (camera id, frame index, number of detections), whether a camera-frame is accepted and
/// what its arrival does to the frame sequence (closing the collected frame, re-anchoring the
/// window grid, opening a new frame). It never looks at detection contents, so a dispatcher can
/// run it on the receiving thread before any per-camera work, and every later stage only
/// applies its decisions. Pure, single-owner, single-threaded object.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/detection.h"
#include "core/types.h"
#include "geometry/camera_rig.h"
#include "tracker/options.h"
#include "tracker/types.h"

namespace mvtrack::tracker {

/// What admitting one camera-frame does to the frame sequence. The events apply in the order
/// of the fields (close, then re-anchor, then open); see WindowBuilder::Add.
struct FrameEvents {
  /// A later frame arrived: the frame being collected is closed first.
  bool close_open_frame = false;
  /// Then the stream restarted: the frame is more than max_frame_jump past the last closed
  /// frame. Open windows are flushed, every track ends, the 2D trackers restart (the stream
  /// epoch advances) and a new window grid starts at this frame.
  bool reanchor = false;
  /// This camera-frame opens a new frame (no frame was being collected).
  bool open_frame = false;
  /// After this camera-frame is stored, its frame is closed: every camera of the rig has
  /// delivered it, so no later camera-frame can join it (what makes the frame's provisional
  /// output as early as its last camera, not a frame period later).
  bool close_after = false;
};

/// The gate's verdict on one camera-frame.
struct FrameAdmission {
  /// kNone when accepted.
  FrameRejection rejection = FrameRejection::kNone;
  /// Why it was rejected (empty when accepted).
  std::string reason;
  /// Index of the camera in the rig; -1 for an unknown camera.
  int camera_index = -1;
  /// What the accepted camera-frame does to the frame sequence (all false when rejected).
  FrameEvents events;
  /// Stream epoch the accepted camera-frame belongs to: 0 at the start, +1 at every end of
  /// stream (re-anchor or Flush). A CameraStage restarts its 2D tracker when it sees a newer
  /// epoch (see CameraStage::Process).
  std::int64_t stream_epoch = 0;
};

/// Admission and frame sequencing (docs/DECISIONS.md "Tracker facade" and "Bad input"):
///  - rejected: an unknown camera, more than max_detections_per_frame detections, a frame older
///    than the frame being collected (or, with none being collected, not newer than the last
///    closed frame), a camera delivering the frame being collected twice. A rejection changes
///    nothing.
///  - a frame later than the one being collected closes it (cameras may arrive in any order
///    within a frame), and so does its last camera: a frame every camera of the rig delivered is
///    closed at once (FrameEvents::close_after; a camera delivering it again is a duplicate);
///    a frame more than max_frame_jump past the last closed frame re-anchors.
/// The decisions depend only on the sequence of headers, never on detection contents.
///
/// Single-owner, single-threaded; deterministic.
class FrameGate {
 public:
  /// `options` must be valid (checked by the caller: Tracker::Create / Pipeline::Create).
  FrameGate(const geometry::CameraRig& rig, const TrackerOptions& options);

  /// Admits or rejects one camera-frame (reads camera_id, frame and detections.size() only).
  FrameAdmission Admit(const core::CameraFrame& frame);

  /// End of stream (Tracker::Flush): the frame being collected counts as closed and the frame
  /// sequence starts over (any frame is accepted next). Returns true when there was a stream to
  /// end; then the stream epoch has advanced.
  bool Flush();

  /// The current stream epoch (see FrameAdmission::stream_epoch).
  std::int64_t stream_epoch() const { return stream_epoch_; }
  /// The frame being collected, if any.
  const std::optional<FrameIndex>& open_frame() const { return open_frame_; }
  /// The newest closed frame of the current stream, if any.
  const std::optional<FrameIndex>& last_closed_frame() const { return last_closed_frame_; }

 private:
  std::map<CameraId, int> index_of_camera_;
  std::int64_t max_detections_per_frame_ = 0;
  std::int64_t max_frame_jump_ = 0;
  std::optional<FrameIndex> open_frame_;
  std::vector<bool> open_cameras_;  // by rig index: delivered the open frame
  std::optional<FrameIndex> last_closed_frame_;
  bool closed_complete_ = false;  // last_closed_frame_ was closed by its last camera
  std::int64_t stream_epoch_ = 0;
};

}  // namespace mvtrack::tracker
