#pragma once
/// @file
/// The algorithm's internal view of people in images: observations in undistorted pixels, 2D
/// tracklets cropped by a sliding window, and 3D tracklets produced per window. Pure data.

#include <algorithm>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/appearance.h"
#include "core/types.h"

namespace mvtrack::core {

/// Observation2D::cut_edges bits.
inline constexpr std::uint8_t kCutLeft = 1;
inline constexpr std::uint8_t kCutRight = 2;
inline constexpr std::uint8_t kCutTop = 4;
inline constexpr std::uint8_t kCutBottom = 8;

/// One person seen by one camera at one frame, in *undistorted* pixel coordinates (the pinhole
/// image of CameraModel::ProjectionMatrix). Box mode has one point (see TrackerOptions); pose
/// mode has one point per joint of the tracker's layout.
struct Observation2D {
  std::vector<Vec2> points_px;
  /// Per-point confidence in [0, 1]; 0 means the point is missing and must not be used.
  std::vector<double> confidence;
  /// |w + h| of the box that encloses the person, in pixels (the normaliser of Eq. 2). > 0.
  double scale_px = 1.0;
  /// Box mode: the edges of the detector's box that touch the image border (kCutLeft | ...,
  /// raw image directions): the person is cut off there, so the box's centre (and every point
  /// taken from it) lies off the person's, towards the inside of the image: a reprojection
  /// residual does not count the part of a deviation that points past a cut edge
  /// (triangulation::ReprojectionResidual), a window person that stands on such boxes is
  /// merged into the person they show (tracker::ProcessWindowJob), and with
  /// TrackerOptions::box_complete_cut the centre is that of the box completed to its 2D track's
  /// whole size (tracker::CameraStage). 0: the whole person is in the image.
  std::uint8_t cut_edges = 0;
  /// The detection's appearance embedding, unit length (core::CheckEmbedding); null when it
  /// had none, it was unusable, or appearance is off. Shared: windows copy observations.
  EmbeddingPtr embedding;
};

/// A 2D tracklet: the observations of one camera's 2D track inside one window (Eq. 3, T_{k,i}).
struct Tracklet2D {
  CameraId camera_id = 0;
  TrackId2D track_id = 0;
  std::vector<FrameIndex> frames;           ///< strictly increasing
  std::vector<Observation2D> observations;  ///< parallel to `frames`

  /// Index into frames/observations of `frame`, or -1.
  int IndexOf(FrameIndex frame) const {
    auto it = std::lower_bound(frames.begin(), frames.end(), frame);
    if (it == frames.end() || *it != frame) return -1;
    return static_cast<int>(it - frames.begin());
  }
};

/// One 2D tracklet that supports a short-term 3D tracklet: which camera's which 2D track, and
/// the frames it was observed in inside the window. The same (camera_id, track_id) in the next
/// window is the same 2D track continuing, the strongest evidence that two short-term 3D
/// tracklets show one person (linking::WindowLinker).
struct TrackletMember {
  CameraId camera_id = 0;
  TrackId2D track_id = 0;
  FrameIndex first_frame = 0;  ///< first observed frame inside the window
  FrameIndex last_frame = 0;   ///< last observed frame inside the window
  int num_observations = 0;    ///< observations inside the window
};

/// One camera's observation of a 3D tracklet's person at one of its frames.
struct PersonView {
  int camera_index = 0;  ///< rig index of the camera
  Observation2D observation;
};

/// A short-term 3D tracklet of one person in one window (U_{k,p}).
struct Tracklet3D {
  std::vector<FrameIndex> frames;  ///< strictly increasing
  /// points[f][k]: point k (box mode: k = 0) at frames[f], world frame, metres.
  std::vector<std::vector<std::optional<Vec3>>> points;
  std::vector<CameraId> cameras;      ///< cameras that supported it, sorted
  std::vector<int> source_tracklets;  ///< indices of its 2D tracklets
  /// The 2D tracklets of source_tracklets as (camera, 2D track) members, sorted by camera id
  /// then track id (filled by tracker::ProcessWindowJob; empty where no window job made it).
  std::vector<TrackletMember> members;
  /// Appearance on: the unit-length mean of the embeddings of its 2D tracklets' observations
  /// (those of the first embedding's dimension), empty when none had one; and how many
  /// embeddings that mean averages.
  std::vector<float> appearance;
  int appearance_count = 0;
  /// Pose mode: per frame (parallel to frames), the observations of its 2D tracklets at that
  /// frame, by rig index (filled by tracker::ProcessWindowJob): what the skeleton fit
  /// (body::FitJoints) fits the joints to. Empty otherwise.
  std::vector<std::vector<PersonView>> views;

  int IndexOf(FrameIndex frame) const {
    auto it = std::lower_bound(frames.begin(), frames.end(), frame);
    if (it == frames.end() || *it != frame) return -1;
    return static_cast<int>(it - frames.begin());
  }
};

}  // namespace mvtrack::core
