#pragma once
/// @file
/// The single-threaded Tracker facade: feed camera-frames (any camera order within a frame,
/// frames in increasing order), get finalized 3D frames out. It chains the whole method of the
/// paper: per-camera SORT -> sliding window (ν, δ) -> cross-view tracklet distance + PDNC ->
/// CMMT -> window linking. Both modes: boxes -> footprints and 2D poses -> 3D poses.
///
/// Thread safety: single-owner, single-threaded (the daemon's pipeline splits the same stages
/// over threads; see docs/ARCHITECTURE.md). Deterministic: output depends only on the input
/// sequence. Never throws on input: bad input is rejected with a reason and counted.

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
#include "tracking2d/sort_tracker.h"
#include "triangulation/triangulation.h"

namespace mvtrack::tracker {

/// What the tracker consumes and produces.
enum class InputMode {
  kBoxes,  ///< boxes -> footprints (association and triangulation on one point per box)
  kPoses,  ///< 2D poses -> 3D poses (association averaged over joints, triangulation per joint)
};

/// Which point of a box represents the person in box mode.
enum class BoxPoint {
  kCenter,        ///< the box centre (the paper's choice for association)
  kBottomCenter,  ///< the middle of the bottom edge (the feet)
};

/// All options of the method; defaults are the paper's (ν=30, δ=20, λ=0.3, φ=7, κ=0.2 m).
struct TrackerOptions {
  InputMode mode = InputMode::kBoxes;
  /// Pose mode: the layout tracks are estimated in; inputs in other layouts are mapped to it.
  core::KeypointLayoutId layout = core::KeypointLayoutId::kCoco17;
  int window_size = 30;  ///< ν, frames
  int window_step = 20;  ///< δ, frames (1 <= δ <= ν)
  BoxPoint box_point = BoxPoint::kCenter;
  /// Height of the floor plane z = ground_height_m in the world frame (z up): footprints lie on it.
  double ground_height_m = 0.0;
  /// Detections with a lower score are ignored (counted as filtered, not as errors).
  double min_detection_score = 0.0;
  /// Pose mode: keypoints with a lower confidence are treated as missing.
  double min_keypoint_confidence = 0.1;
  /// Pose mode: a pose with fewer usable keypoints is ignored (counted as filtered).
  int min_pose_keypoints = 4;
  /// A 2D tracklet needs at least this many observations in a window to be associated.
  int min_tracklet_length = 2;
  /// A frame index more than this far ahead of the newest frame re-anchors the window grid
  /// (the stream restarted): open windows are flushed and every track ends.
  std::int64_t max_frame_jump = 1000;
  /// Validation limits for incoming detections (image size comes from each camera).
  double box_margin_fraction = 0.5;
  int max_detections_per_frame = 1000;

  tracking2d::SortOptions sort;
  association::AssociationOptions association;
  triangulation::TriangulationOptions triangulation;
  linking::LinkerOptions linking;

  /// Validates these options and the nested ones; on failure `why` names the field.
  bool Validate(std::string* why) const;
};

/// One 3D track in one finalized frame.
struct Track3D {
  TrackId3D id = 0;
  /// Footprint on the floor plane (world frame, metres).
  Vec3 position = Vec3::Zero();
  /// Pose mode: one entry per joint of TrackerOptions::layout (world, metres); empty in box mode.
  std::vector<std::optional<Vec3>> joints;
  /// Fraction of the track's points triangulated in this frame, in [0, 1].
  double confidence = 0.0;
  /// Cameras whose 2D tracklets supported the track in the window that produced this frame.
  std::vector<CameraId> cameras;
  /// Frames since the track was born (this frame minus its first frame).
  std::int64_t age_frames = 0;
  linking::TrackState state = linking::TrackState::kConfirmed;
};

/// All confirmed tracks of one finalized frame, sorted by id.
struct Frame3D {
  FrameIndex frame = 0;
  Utime utime = 0;  ///< capture time: the smallest utime among the frame's camera-frames
  std::vector<Track3D> tracks;
};

/// Why a camera-frame was rejected as a whole.
enum class FrameRejection {
  kNone,
  kUnknownCamera,     ///< camera id not in the rig
  kStaleFrame,        ///< frame index older than the frame being collected
  kDuplicateCamera,   ///< this camera already delivered this frame
  kTooManyDetections, ///< more detections than max_detections_per_frame
};

/// What happened to one Add() call.
struct AddResult {
  FrameRejection rejection = FrameRejection::kNone;
  std::string reason;           ///< why the frame (or the first bad detection) was rejected
  int detections_used = 0;
  int detections_rejected = 0;  ///< invalid detections dropped (ValidateDetection)
  int detections_repaired = 0;  ///< detections kept with some keypoints invalidated
  int detections_filtered = 0;  ///< valid but below score / keypoint thresholds
  std::vector<Frame3D> finalized;  ///< frames finalized by this call, in increasing order
};

/// Cumulative counters.
struct TrackerStats {
  std::int64_t camera_frames_accepted = 0;
  std::int64_t camera_frames_rejected = 0;
  std::map<FrameRejection, std::int64_t> rejections;
  std::int64_t detections_used = 0;
  std::int64_t detections_rejected = 0;
  std::int64_t detections_repaired = 0;
  std::int64_t detections_filtered = 0;
  std::int64_t frames_finalized = 0;
  std::int64_t windows_processed = 0;
  std::int64_t reanchors = 0;
  std::int64_t tracks_born = 0;
};

/// Output of one window (exposed for tests, ablations and the pipeline).
struct WindowOutput {
  std::int64_t window_id = 0;
  FrameIndex begin = 0, end = 0;  ///< [begin, end)
  std::vector<core::Tracklet2D> tracklets;
  std::vector<std::vector<int>> clusters;
  std::vector<core::Tracklet3D> persons;   ///< one per cluster with >= 2 cameras
  linking::LinkResult link;
};

class Tracker {
 public:
  /// Returns nullptr and sets `why` when the options are invalid or the rig has fewer than two
  /// cameras (a single camera cannot triangulate anything).
  static std::unique_ptr<Tracker> Create(geometry::CameraRig rig, TrackerOptions options,
                                         std::string* why);

  /// Adds one camera's detections for one frame. A frame is collected until a camera-frame of
  /// a later frame arrives; then it is closed, and windows that became complete are processed.
  AddResult Add(const core::CameraFrame& frame);

  /// End of stream: closes the open frame, processes the remaining (partial) windows and
  /// returns every frame not yet finalized. The tracker can be fed again afterwards (a new
  /// window grid starts; track ids keep increasing).
  std::vector<Frame3D> Flush();

  const TrackerStats& stats() const { return stats_; }
  const TrackerOptions& options() const { return options_; }
  const geometry::CameraRig& rig() const { return rig_; }
  /// Number of points per observation (1 in box mode, the layout's joints in pose mode).
  int num_points() const { return num_points_; }
  /// The most recent processed window (for tests and diagnostics).
  const std::optional<WindowOutput>& last_window() const { return last_window_; }

 private:
  Tracker(geometry::CameraRig rig, TrackerOptions options);

  struct TimedObservation {
    FrameIndex frame;
    core::Observation2D observation;
  };
  struct CameraState {
    tracking2d::SortTracker sort;
    std::optional<FrameIndex> last_frame;
    /// Observations of each live 2D track, oldest first.
    std::map<TrackId2D, std::vector<TimedObservation>> tracks;
  };
  struct PendingFrame {
    FrameIndex frame;
    Utime utime;
    /// Per finalizing window: the tracks of this frame (filled when its window is linked).
    std::vector<Track3D> tracks;
    bool final = false;
  };

  // Converts a validated detection to an observation; nullopt if filtered.
  std::optional<core::Observation2D> MakeObservation(const geometry::CameraModel& camera,
                                                     const core::Detection2D& detection,
                                                     core::BoxPx* sort_box) const;
  void CloseOpenFrame(std::vector<Frame3D>* out);
  void ProcessWindowsUpTo(FrameIndex last_closed, bool flushing, std::vector<Frame3D>* out);
  void ProcessWindow(std::int64_t window_id, FrameIndex begin, FrameIndex end,
                     FrameIndex finalize_from, FrameIndex finalize_to, std::vector<Frame3D>* out);
  void Reanchor(std::vector<Frame3D>* out);
  void EndStream(std::vector<Frame3D>* out);
  void EmitFinal(FrameIndex up_to, std::vector<Frame3D>* out);
  Vec3 FootprintOf(const std::vector<std::optional<Vec3>>& points) const;

  geometry::CameraRig rig_;
  TrackerOptions options_;
  int num_points_ = 1;
  std::vector<CameraState> cameras_;  // by rig index
  std::map<core::KeypointLayoutId, core::KeypointMapping> mappings_;

  // Frame being collected.
  std::optional<FrameIndex> open_frame_;
  Utime open_utime_ = 0;
  std::vector<bool> open_cameras_;  // by rig index: delivered the open frame

  // Window grid.
  std::optional<FrameIndex> grid_origin_;  // F0
  std::int64_t window_id_offset_ = 0;      // added to grid window indices (re-anchoring)
  std::int64_t next_window_ = 0;           // grid index of the next window to process
  std::optional<FrameIndex> last_closed_frame_;

  linking::WindowLinker linker_;
  std::map<TrackId3D, FrameIndex> first_frame_of_track_;
  std::map<FrameIndex, PendingFrame> pending_;  // closed frames not yet emitted
  std::optional<WindowOutput> last_window_;
  TrackerStats stats_;
};

/// Human-readable name of a rejection.
const char* ToString(FrameRejection rejection);

}  // namespace mvtrack::tracker
