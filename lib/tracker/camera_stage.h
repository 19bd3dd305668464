#pragma once
/// @file
/// CameraStage: everything that happens to one camera's detections before the sliding window —
/// detection validation (core::ValidateDetection), conversion to observations in undistorted
/// pixels (pose mode: keypoint layout mapping) and the camera's own SORT tracker
/// (tracking2d::SortTracker, the paper's single-view multi-person tracking). One instance per
/// camera; single-owner, single-threaded; pure (no threads, I/O or clock).

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/appearance.h"
#include "core/detection.h"
#include "core/keypoint_layout.h"
#include "core/observation.h"
#include "core/types.h"
#include "geometry/camera_model.h"
#include "tracker/frame_period.h"
#include "tracker/options.h"
#include "tracking2d/sort_tracker.h"

namespace mvtrack::tracker {

/// The output of one camera-frame: the observations of this frame that belong to confirmed 2D
/// tracks of the camera.
struct TrackedCameraFrame {
  int camera_index = -1;  ///< index of the camera in the rig
  FrameIndex frame = 0;   ///< frame index of the camera-frame
  Utime utime = 0;        ///< capture time of the camera-frame, µs
  /// (2D track id, observation in undistorted pixels), sorted by track id.
  std::vector<std::pair<TrackId2D, core::Observation2D>> observations;
};

/// What happened to the detections of one camera-frame.
struct CameraStageCounters {
  int detections_used = 0;      ///< converted to observations and given to SORT
  int detections_rejected = 0;  ///< invalid detections dropped (core::ValidateDetection)
  int detections_repaired = 0;  ///< detections kept with some keypoints invalidated
  int detections_filtered = 0;  ///< valid but below the score / keypoint thresholds
  /// Why the first rejected detection of the frame was rejected (empty if none was).
  std::string first_rejection_reason;
  /// Appearance on: embeddings attached to observations / dropped as unusable (oversized or
  /// non-finite: core::ValidateDetection; zero, or another dimension or model than the stream:
  /// core::CheckEmbedding); the detection is used without it.
  int embeddings_used = 0;
  int embeddings_dropped = 0;
  /// Why the first dropped embedding of the frame was dropped (empty if none was).
  std::string first_embedding_reason;
  /// Appearance on: memory of the camera's SORT galleries after this frame, bytes (0 off).
  std::int64_t sort_gallery_bytes = 0;
};

/// Per-camera stage: validation, observation, SORT. See the file comment.
///
/// Single-owner, single-threaded object. Its output depends only on the sequence of
/// (camera-frame, stream epoch) it is given.
class CameraStage {
 public:
  /// `camera` is the rig's camera at `camera_index`; `options` must be valid (checked by the
  /// caller: Tracker::Create / Pipeline::Create).
  CameraStage(geometry::CameraModel camera, int camera_index, const TrackerOptions& options);

  /// Processes one admitted camera-frame of this camera (see FrameGate): validates every
  /// detection, converts the usable ones to observations and runs SORT on them. Frames must
  /// increase within a stream epoch; a newer `stream_epoch` than the previous call's restarts
  /// SORT first (the stream ended: re-anchor or flush). `counters` (not null) is overwritten.
  TrackedCameraFrame Process(const core::CameraFrame& frame,
                             std::int64_t stream_epoch,
                             CameraStageCounters* counters);

  /// Index of the camera in the rig.
  int camera_index() const { return camera_index_; }
  /// The camera's 2D tracker (diagnostics).
  const tracking2d::SortTracker& sort() const { return sort_; }
  /// The dimension and model this camera's embeddings must have (fixed by the first usable one).
  const core::EmbeddingStream& embedding_stream() const { return embedding_stream_; }

 private:
  // Converts a validated detection to an observation; nullopt if filtered. Sets `sort_box` to
  // the box SORT tracks (box mode: the detection's box; pose mode: the box of its usable
  // keypoints).
  // Image direction (pointing down the image) of the world's vertical at an undistorted pixel.
  Vec2 VerticalDirectionAt(const Vec2& undistorted_px) const;
  // Whether the ray through an undistorted pixel is steeper than box_ends_max_elevation_deg.
  bool SteeperThanEndsLimit(const Vec2& undistorted_px) const;
  std::optional<core::Observation2D> MakeObservation(const core::Detection2D& detection,
                                                     core::BoxPx* sort_box) const;

  geometry::CameraModel camera_;
  int camera_index_ = 0;
  TrackerOptions options_;
  int num_points_ = 1;
  std::map<core::KeypointLayoutId, core::KeypointMapping> mappings_;
  tracking2d::SortTracker sort_;
  core::EmbeddingStream embedding_stream_;
  std::vector<const std::vector<float>*> embeddings_;  // Process scratch, parallel to boxes_  //
                                                       // outlives stream epochs: the camera's model
  // This camera's frame period (its own capture times) and the one SORT's options were last
  // scaled to (TrackerOptions::reference_fps).
  FramePeriod period_;
  double sort_seconds_per_frame_ = 0.0;
  std::size_t frames_since_period_ = FramePeriod::kFrames - 1;  // the first full window is due
  // Box ends: K^-1, the camera-to-world rotation and the vanishing point of the world's up.
  Mat3 k_inverse_;
  Mat3 world_from_cam_;
  Vec3 up_vanishing_;
  double sin_ends_limit_ = 1.0;  // sin(box_ends_max_elevation_deg)
  std::int64_t stream_epoch_ = 0;
  // Scratch of Process, kept between calls for its capacity: the boxes SORT tracks and the
  // observations of the usable detections (parallel).
  std::vector<core::BoxPx> boxes_;
  std::vector<core::Observation2D> observations_;
  // Box mode: per 2D track, the size (w, h) of its latest box that the image border did not
  // cut and that box's frame: completes the track's cut boxes (CompleteCutBox).
  struct WholeSize {
    double width = 0.0;
    double height = 0.0;
    FrameIndex frame = 0;
  };
  std::map<TrackId2D, WholeSize> whole_size_;
  // Replaces a cut observation's centre by that of its box completed to the track's whole size.
  void CompleteCutBox(TrackId2D track,
                      FrameIndex frame,
                      const core::BoxPx& box,
                      core::Observation2D* obs);
};

}  // namespace mvtrack::tracker
