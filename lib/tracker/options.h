#pragma once
/// @file
/// Options of the whole tracking method (all stages of lib/tracker). Pure data plus validation.

#include <cstdint>
#include <string>
#include <vector>

#include "association/options.h"
#include "core/appearance.h"
#include "core/keypoint_layout.h"
#include "geometry/camera_rig.h"
#include "linking/window_linker.h"
#include "tracking2d/sort_tracker.h"
#include "triangulation/refinement.h"
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
  /// The box centre (point 0, associated and triangulated by CMMT as kCenter) plus the middle
  /// of the bottom edge (point 1, the feet) and of the top edge (point 2, the head), each
  /// marked missing when its box edge touches the image border (the person is cut off
  /// there). The ends take part in cross-view association (Eq. 2 averaged over the usable
  /// points) and are triangulated per frame from the person's views (N-view DLT, not CMMT,
  /// which stays on the centre); feet off the floor or a head at an impossible height mean
  /// that rays of different people crossed, and such frames are removed
  /// (RefinementOptions::box_bottom_*, box_top_*). docs/DECISIONS.md "Box points".
  kCenterEnds,
};

/// All options of the method; defaults are the paper's (ν=30, δ=20, λ=0.3, φ=7, κ=0.2 m).
struct TrackerOptions {
  /// Boxes or poses in, footprints or 3D poses out.
  InputMode mode = InputMode::kBoxes;
  /// Pose mode: the layout tracks are estimated in; inputs in other layouts are mapped to it.
  core::KeypointLayoutId layout = core::KeypointLayoutId::kCoco17;
  int window_size = 30;  ///< ν, frames at reference_fps or faster (AtFrameRate)
  int window_step = 20;  ///< δ, frames (1 <= δ <= ν), likewise
  /// The frame rate the frame-count options are set for: window_size, window_step,
  /// min_tracklet_length, sort.max_age, sort.min_hits, triangulation.phi,
  /// refinement.box_min_duplicate_frames and refinement.smooth_half_window count frames of a stream
  /// at this rate or faster, and sort.iou_threshold holds at this rate. A slower stream (its rate
  /// measured from the capture times) scales them by its rate / reference_fps (counts rounded up;
  /// AtFrameRate), so each keeps its duration (ν = 30 frames = 1.2 s, 3 frames at 2 fps) and SORT
  /// accepts the longer steps between frames (SortOptions::motion_buffer). 25: the paper's defaults
  /// were set on 25 fps data (Shelf, Campus), and 30 fps streams keep them unchanged. 0: counts are
  /// frames at any rate.
  double reference_fps = 25.0;
  /// Box mode: which point of the box is associated and triangulated.
  BoxPoint box_point = BoxPoint::kCenterEnds;
  /// Box mode with box_point center_ends: the box ends also take part in cross-view
  /// association (else only the centre does, as the paper's box centre).
  bool box_ends_in_association = true;
  /// Box mode, box_point center or center_ends: a box cut by the image border whose 2D track
  /// had a whole box within the last 60 frames is completed to that box's size (extended past
  /// the cut edge, never shrunk) before its centre is taken: the person's centre, not the
  /// visible part's. false: the cut box's own centre.
  bool box_complete_cut = true;
  /// Box mode with box_point center_ends: the ends of a box are used only when the camera
  /// looks at it at most this steeply (the angle of the ray through the box centre below the
  /// horizontal, degrees). A camera looking down on a person sees the top of the head inside
  /// the box and the nearer foot at its bottom, so its box ends are not the same 3D points as
  /// a side view's. In [0, 90].
  double box_ends_max_elevation_deg = 40.0;
  /// Height of the floor plane z = ground_height_m in the world frame (z up): footprints lie on it.
  double ground_height_m = 0.0;
  /// Box mode, monocular continuation (LinkerOptions::monocular_max_s): a frame one camera alone
  /// places counts only where the ray through the feet descends at least this steeply below the
  /// horizontal (degrees): a pixel's error moves the floor point by the camera height / sin^2
  /// of that angle, 13 times more at 15 degrees than at 60. In [0, 90].
  double monocular_min_elevation_deg = 20.0;
  /// A confirmed track at least 0.5 s old that is missing for at most this long (seconds of
  /// stream time) and then continues under the same id gets the frames in between, when they
  /// are not output yet, interpolated point by point between its frames on both sides (cameras
  /// empty: no view saw it). Where one camera pair cannot place a person (a camera dark, two people
  /// along the other pair's epipolar line) the track's own motion can. 0 disables. In [0, 10].
  double bridge_max_gap_s = 0.6;
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
  /// Validation limit for incoming boxes (image size comes from each camera): how far a box may
  /// stick out of the image, as a fraction of the image size.
  double box_margin_fraction = 0.5;
  /// A camera-frame with more detections is rejected as a whole.
  int max_detections_per_frame = 1000;

  tracking2d::SortOptions sort;                       ///< per-camera SORT
  association::AssociationOptions association;        ///< Eq. 2-4 and PDNC
  triangulation::TriangulationOptions triangulation;  ///< CMMT (Algorithm 2)
  linking::LinkerOptions linking;                     ///< Eq. 8-9
  /// Pose mode: per-window refinement after CMMT (duplicate merging, fragment removal, temporal
  /// outlier rejection, completion of joints no camera pair could triangulate;
  /// docs/ACCURACY.md). Not applied in box mode.
  triangulation::RefinementOptions refinement;
  /// Appearance embeddings (the paper's "w/ appearance" variant); on by default, which changes
  /// nothing on a stream without embeddings.
  core::AppearanceOptions appearance;

  /// Validates these options and the nested ones; on failure `why` names the field.
  bool Validate(std::string* why) const;
};

/// The options in effect for a stream whose frames are `seconds_per_frame` apart (finite, > 0):
/// `options` unchanged when reference_fps is 0 or the stream runs at reference_fps or faster;
/// else with f = (1 / seconds_per_frame) / reference_fps < 1: every frame count n of
/// TrackerOptions::reference_fps becomes max(its minimum, ceil(n f)) (ν >= 2, φ >= 1 unless 0,
/// all others >= 1; δ <= ν), sort.motion_buffer becomes kMaxReidSpeedMps x (seconds_per_frame
/// - 1 / reference_fps) / 1.7 m (box heights; the IoU threshold stays) and
/// sort.process_noise_scale (1 / f)^3. The result is
/// valid when `options` is. docs/DECISIONS.md "Time".
TrackerOptions AtFrameRate(const TrackerOptions& options, double seconds_per_frame);

/// The cross-view association options a window job uses: `options.association` with the box
/// points (one point, or the feet compared on the floor at ground_height_m) and the appearance
/// weights of `options` applied.
association::AssociationOptions AssociationOptionsInEffect(const TrackerOptions& options);

/// `rig` with the pairs of cameras that can see one place marked
/// (geometry::CameraRig::ComputeSharedViews for a person on the floor z = ground_height_m):
/// the rig a tracker associates with, so tracklets of two cameras that never see one place
/// are never one person (issue 43, docs/DECISIONS.md "Cameras that never see one place").
geometry::CameraRig WithSharedViews(geometry::CameraRig rig, const TrackerOptions& options);

/// AtFrameRate(options, seconds_per_frame).sort, without copying the rest.
tracking2d::SortOptions SortOptionsAtFrameRate(const TrackerOptions& options,
                                               double seconds_per_frame);

/// Number of points per observation under `options`: 1 in box mode, the layout's joints in
/// pose mode. `options` must be valid.
int NumPoints(const TrackerOptions& options);

/// The point indices whose mean is a person's footprint when all are triangulated (pose mode:
/// the hips of the layout, box mode: the box point); otherwise the mean of the triangulated
/// points (linking::FrameFootprint). Shared by the window refinement, the linker and the
/// output.
std::vector<int> FootprintPoints(const TrackerOptions& options);

/// Points CMMT triangulates (the first NumTriangulatedPoints of every observation): all of
/// them, except for BoxPoint::kCenterEnds, whose box ends are triangulated by DLT.
int NumTriangulatedPoints(const TrackerOptions& options);

/// Box mode with BoxPoint::kCenterEnds: the indices of the centre, bottom (feet) and top
/// (head) points.
inline constexpr int kBoxCenterPoint = 0;
inline constexpr int kBoxBottomPoint = 1;
inline constexpr int kBoxTopPoint = 2;

}  // namespace mvtrack::tracker
