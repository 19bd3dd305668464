#pragma once
/// @file
/// Options of the whole tracking method (all stages of lib/tracker). Pure data plus validation.

#include <cstdint>
#include <string>

#include "association/options.h"
#include "core/keypoint_layout.h"
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
};

/// All options of the method; defaults are the paper's (ν=30, δ=20, λ=0.3, φ=7, κ=0.2 m).
struct TrackerOptions {
  /// Boxes or poses in, footprints or 3D poses out.
  InputMode mode = InputMode::kBoxes;
  /// Pose mode: the layout tracks are estimated in; inputs in other layouts are mapped to it.
  core::KeypointLayoutId layout = core::KeypointLayoutId::kCoco17;
  int window_size = 30;  ///< ν, frames
  int window_step = 20;  ///< δ, frames (1 <= δ <= ν)
  /// Box mode: which point of the box is associated and triangulated.
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
  /// Validation limit for incoming boxes (image size comes from each camera): how far a box may
  /// stick out of the image, as a fraction of the image size.
  double box_margin_fraction = 0.5;
  /// A camera-frame with more detections is rejected as a whole.
  int max_detections_per_frame = 1000;

  tracking2d::SortOptions sort;                     ///< per-camera SORT
  association::AssociationOptions association;      ///< Eq. 2-4 and PDNC
  triangulation::TriangulationOptions triangulation;  ///< CMMT (Algorithm 2)
  linking::LinkerOptions linking;                   ///< Eq. 8-9
  /// Pose mode: per-window refinement after CMMT (duplicate merging, fragment removal, temporal
  /// outlier rejection, completion of joints no camera pair could triangulate;
  /// docs/ACCURACY.md). Not applied in box mode.
  triangulation::RefinementOptions refinement;

  /// Validates these options and the nested ones; on failure `why` names the field.
  bool Validate(std::string* why) const;
};

/// Number of points per observation under `options`: 1 in box mode, the layout's joints in
/// pose mode. `options` must be valid.
int NumPoints(const TrackerOptions& options);

}  // namespace mvtrack::tracker
