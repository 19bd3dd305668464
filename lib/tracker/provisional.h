#pragma once
/// @file
/// The provisional ("now") layer: where each confirmed track is in a frame as soon as that frame
/// is closed, before any window containing it has been processed. The windowed output lags by
/// about a window (ν frames plus the window's processing, 0.5-0.9 s at 30 fps); the provisional
/// layer reuses the association of the latest linked window for the frame's own 2D tracks:
/// each confirmed track's 2D tracks (linking::LinkedTrack::members) that are seen in the frame
/// are triangulated together (CMMT on the frame's observed points, the window's height gate in
/// box mode) or, seen by one camera only in box mode, placed on the floor below the box
/// (FeetOnFloor). A track not placed so (unseen, or views that do not meet) is not in the frame.
/// docs/DECISIONS.md "The provisional layer". Pure, single-owner, single-threaded object.

#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "core/observation.h"
#include "core/types.h"
#include "geometry/camera_rig.h"
#include "linking/window_linker.h"
#include "tracker/options.h"
#include "tracker/types.h"
#include "triangulation/triangulation.h"

namespace mvtrack::tracker {

/// One camera's observation of one of its 2D tracks at a closed frame.
struct FrameView {
  int camera_index = 0;    ///< rig index of the camera
  TrackId2D track_id = 0;  ///< the camera's 2D track
  core::Observation2D observation;
};

/// Estimates the provisional frames. Deterministic: the output depends only on the sequence
/// of calls (OnLinked after every linked window, Estimate for every closed frame, EndStream at
/// every end of stream), which tracker::Tracker and pipeline::Pipeline make in the same order.
class ProvisionalEstimator {
 public:
  /// `options` must be valid; `rig`: the cameras FrameView::camera_index refers to.
  ProvisionalEstimator(const geometry::CameraRig& rig, const TrackerOptions& options);

  /// Takes the confirmed tracks of `linker` after a window was linked, with the 2D tracks
  /// that belong to each: a 2D track that is a member of several tracks belongs to the one
  /// that saw it last (ties: the lowest id).
  void OnLinked(const linking::WindowLinker& linker);

  /// The provisional frame `frame` (sorted by id, state kConfirmed; `cameras`: the views that
  /// placed it; confidence: the fraction of the triangulated points placed, 0 for one camera):
  /// `views` are the frame's observations of every camera (any order).
  Frame3D Estimate(FrameIndex frame, Utime utime, const std::vector<FrameView>& views);

  /// The stream ended: every track is forgotten (new windows bring new ids).
  void EndStream();

 private:
  struct Track {
    TrackId3D id = 0;
    FrameIndex first_frame = 0;  // its first footprint (LinkedTrack::first_seen_frame)
    // Its latest footprint, placed by this layer or by a window, whichever is later.
    FrameIndex last_frame = 0;
    Vec2 last_xy = Vec2::Zero();
  };

  // Triangulates the gathered views_ of one track; nullopt when no point is triangulated.
  std::optional<std::vector<std::optional<Vec3>>> Triangulate(FrameIndex frame);

  const geometry::CameraRig& rig_;
  InputMode mode_ = InputMode::kBoxes;
  int num_points_ = 1;
  int num_triangulated_points_ = 1;
  std::vector<int> footprint_points_;
  double ground_height_m_ = 0.0;
  double min_height_m_ = 0.0;  // box mode: the plausible heights of the box centre
  double max_height_m_ = 0.0;
  TrackerOptions options_;
  triangulation::PersonTriangulator triangulator_;

  double seconds_per_frame_ = 1.0 / 30.0;  // of the latest linked window
  std::vector<Track> tracks_;              // the confirmed tracks, by id
  // 2D track -> tracks_ index of its owner (kNotOutput in the .cc: a tentative owner).
  std::map<std::pair<CameraId, TrackId2D>, std::size_t> owner_;
  // Estimate's scratch.
  std::vector<std::vector<const FrameView*>> views_of_track_;
  std::vector<core::Tracklet2D> tracklets_;
  std::vector<int> cluster_;
};

}  // namespace mvtrack::tracker
