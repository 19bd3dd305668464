#pragma once
/// @file
/// The single-threaded Tracker facade: feed camera-frames (any camera order within a frame,
/// frames in increasing order), get finalized 3D frames out. It chains the whole method of the
/// paper: per-camera SORT -> sliding window (ν, δ) -> cross-view tracklet distance + PDNC ->
/// CMMT -> window linking. Both modes: boxes -> footprints and 2D poses -> 3D poses.
///
/// The Tracker is the inline composition of the pure stages FrameGate (admission, frame
/// sequencing), CameraStage (one per camera: validation, observations, SORT), WindowBuilder
/// (frames -> WindowJobs), ProcessWindowJob (association + CMMT) and WindowFinalizer (linking,
/// output). The threaded lib/pipeline runs exactly the same stages over threads and produces
/// bit-identical output.
///
/// Thread safety: single-owner, single-threaded. Deterministic: output depends only on the
/// input sequence. Never throws on input: bad input is rejected with a reason and counted.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "association/association.h"
#include "core/detection.h"
#include "core/keypoint_layout.h"
#include "core/observation.h"
#include "core/types.h"
#include "geometry/camera_rig.h"
#include "linking/window_linker.h"
#include "tracker/camera_stage.h"
#include "tracker/frame_gate.h"
#include "tracker/options.h"
#include "tracker/provisional.h"
#include "tracker/types.h"
#include "tracker/window_builder.h"
#include "tracker/window_finalizer.h"
#include "tracker/window_job.h"
#include "tracking2d/sort_tracker.h"
#include "triangulation/triangulation.h"

namespace mvtrack::tracker {

/// What happened to one Add() call.
struct AddResult {
  /// kNone when the camera-frame was accepted.
  FrameRejection rejection = FrameRejection::kNone;
  std::string reason;              ///< why the frame (or the first bad detection) was rejected
  int detections_used = 0;         ///< converted to observations and given to SORT
  int detections_rejected = 0;     ///< invalid detections dropped (ValidateDetection)
  int detections_repaired = 0;     ///< detections kept with some keypoints invalidated
  int detections_filtered = 0;     ///< valid but below score / keypoint thresholds
  int embeddings_used = 0;         ///< appearance on: embeddings attached to observations
  int embeddings_dropped = 0;      ///< appearance on: unusable embeddings (dropped)
  std::vector<Frame3D> finalized;  ///< frames finalized by this call, in increasing order
};

/// Cumulative counters.
struct TrackerStats {
  std::int64_t camera_frames_accepted = 0;            ///< camera-frames admitted
  std::int64_t camera_frames_rejected = 0;            ///< camera-frames rejected as a whole
  std::map<FrameRejection, std::int64_t> rejections;  ///< rejected camera-frames by reason
  std::int64_t detections_used = 0;                   ///< see AddResult
  std::int64_t detections_rejected = 0;               ///< see AddResult
  std::int64_t detections_repaired = 0;               ///< see AddResult
  std::int64_t detections_filtered = 0;               ///< see AddResult
  std::int64_t frames_finalized = 0;                  ///< Frame3D output
  std::int64_t windows_processed = 0;                 ///< windows linked
  std::int64_t reanchors = 0;                         ///< stream restarts (max_frame_jump exceeded)
  std::int64_t tracks_born = 0;                       ///< long-term 3D tracks started
  std::int64_t tracks_revived = 0;      ///< ended tracks that came back by appearance (same id)
  std::int64_t embeddings_used = 0;     ///< appearance on: embeddings attached to observations
  std::int64_t embeddings_dropped = 0;  ///< appearance on: unusable embeddings (dropped)
  /// Appearance on: memory of the galleries now (GalleryMemory::total()), bytes.
  std::int64_t gallery_bytes = 0;
};

/// The memory of the appearance galleries, in bytes: the window linker's (tracks and departed
/// tracks) plus each camera's SORT galleries, each as last reported.
class GalleryMemory {
 public:
  explicit GalleryMemory(std::size_t num_cameras = 0) : sort_(num_cameras, 0) {}
  /// The linker's galleries now.
  void SetLinker(std::int64_t bytes) { linker_ = bytes; }
  /// Camera `camera_index`'s SORT galleries now (a rig index below num_cameras).
  void SetCamera(std::size_t camera_index, std::int64_t bytes) {
    sort_total_ += bytes - sort_.at(camera_index);
    sort_[camera_index] = bytes;
  }
  /// Linker plus every camera.
  std::int64_t total() const { return linker_ + sort_total_; }

 private:
  std::vector<std::int64_t> sort_;
  std::int64_t sort_total_ = 0;
  std::int64_t linker_ = 0;
};

/// Output of one window (exposed for tests, ablations and diagnostics).
struct WindowOutput {
  std::int64_t window_id = 0;               ///< see WindowJob
  FrameIndex begin = 0, end = 0;            ///< [begin, end)
  std::vector<core::Tracklet2D> tracklets;  ///< the job's 2D tracklets
  std::vector<std::vector<int>> clusters;   ///< PDNC clusters of indices into `tracklets`
  std::vector<core::Tracklet3D> persons;    ///< see WindowResult::persons
  linking::LinkResult link;                 ///< how `persons` were linked
};

/// The single-threaded tracker; see the file comment.
class Tracker {
 public:
  /// Returns nullptr and sets `why` when the options are invalid or the rig has fewer than two
  /// cameras (a single camera cannot triangulate anything).
  /// With `provisional`, every closed frame also gets a provisional frame (ProvisionalEstimator,
  /// taken with TakeProvisional), estimated after the windows linked before it.
  static std::unique_ptr<Tracker> Create(geometry::CameraRig rig,
                                         TrackerOptions options,
                                         std::string* why,
                                         bool provisional = false);

  /// Adds one camera's detections for one frame. A frame is collected until a camera-frame of
  /// a later frame arrives or every camera delivered it; then it is closed, and windows that
  /// became complete are processed.
  AddResult Add(const core::CameraFrame& frame);

  /// End of stream: closes the open frame, processes the remaining (partial) windows and
  /// returns every frame not yet finalized. The tracker can be fed again afterwards (a new
  /// window grid starts; track ids keep increasing).
  std::vector<Frame3D> Flush();

  /// The provisional frames of the frames closed since the previous call, in increasing frame
  /// order (empty unless made with `provisional`).
  std::vector<Frame3D> TakeProvisional();

  /// Cumulative counters.
  const TrackerStats& stats() const { return stats_; }
  /// The options in use.
  const TrackerOptions& options() const { return options_; }
  /// The camera rig in use.
  const geometry::CameraRig& rig() const { return rig_; }
  /// Number of points per observation (1 in box mode, the layout's joints in pose mode).
  int num_points() const { return num_points_; }
  /// The window linker with its alive long-term tracks (for tests and diagnostics).
  const linking::WindowLinker& linker() const { return finalizer_.linker(); }
  /// The most recent processed window (for tests and diagnostics).
  const std::optional<WindowOutput>& last_window() const { return last_window_; }

 private:
  Tracker(geometry::CameraRig rig, TrackerOptions options, bool provisional);

  // Applies the builder's outputs in order: closed frames and stream ends to the finalizer,
  // window jobs through ProcessWindowJob and then the finalizer.
  void RunOutputs(std::vector<BuilderOutput>* outputs, std::vector<Frame3D>* finalized);

  geometry::CameraRig rig_;
  TrackerOptions options_;
  int num_points_ = 1;
  FrameGate gate_;
  std::vector<CameraStage> cameras_;  // by rig index
  WindowBuilder builder_;
  WindowWorkspace workspace_;
  WindowFinalizer finalizer_;
  std::optional<ProvisionalEstimator> provisional_;  // when made with `provisional`
  std::vector<Frame3D> provisional_frames_;          // not taken yet
  std::optional<WindowOutput> last_window_;
  TrackerStats stats_;
  GalleryMemory gallery_memory_;
  std::vector<BuilderOutput> outputs_;  // Add's scratch, emptied after each call
};

}  // namespace mvtrack::tracker
