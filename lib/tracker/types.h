#pragma once
/// @file
/// Output and rejection types shared by the tracker stages, the Tracker facade and the
/// threaded pipeline. Pure data.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/types.h"
#include "linking/window_linker.h"

namespace mvtrack::tracker {

/// One 3D track in one finalized frame.
struct Track3D {
  TrackId3D id = 0;
  /// Footprint on the floor plane (world frame, metres).
  Vec3 position = Vec3::Zero();
  /// Pose mode: one entry per joint of TrackerOptions::layout (world, metres); empty in box mode.
  std::vector<std::optional<Vec3>> joints;
  /// Pose mode with refinement.fit_skeleton: the track's bone lengths, one per bone of the
  /// layout (core::KeypointLayout::bones), metres, 0 where not known yet; empty otherwise.
  std::vector<double> bone_lengths;
  /// Fraction of the track's points triangulated in this frame, in [0, 1].
  double confidence = 0.0;
  /// Cameras whose 2D tracklets supported the track in the window that produced this frame.
  std::vector<CameraId> cameras;
  /// Frames since the track was born (this frame minus its first frame).
  std::int64_t age_frames = 0;
  /// Life-cycle state of the track in the window that produced this frame.
  linking::TrackState state = linking::TrackState::kConfirmed;
  /// A site's stitched output (issue 43): the zones whose trackers saw the person at this
  /// frame, indices into Frame3D::zones, ascending; empty in one tracker's output.
  std::vector<int> zones;
};

/// All confirmed tracks of one finalized frame, sorted by id.
struct Frame3D {
  FrameIndex frame = 0;  ///< frame index of the synchronized capture
  Utime utime = 0;       ///< capture time: the smallest utime among the frame's camera-frames
  std::vector<Track3D> tracks;  ///< sorted by id
  /// A site's stitched output (issue 43): the site's zone names, in the zones file's order;
  /// empty in one tracker's output.
  std::vector<std::string> zones;
};

/// Sorts `frame`'s tracks by id (stable) and returns an id that appears more than once (the
/// smallest), or nullopt when the ids are unique: the check of every reader of track files.
std::optional<TrackId3D> SortTracksById(Frame3D* frame);

/// Why a camera-frame was rejected as a whole.
enum class FrameRejection {
  kNone,               ///< not rejected
  kUnknownCamera,      ///< camera id not in the rig
  kStaleFrame,         ///< frame index older than the frame being collected
  kDuplicateCamera,    ///< this camera already delivered this frame
  kTooManyDetections,  ///< more detections than max_detections_per_frame
  kBadFrameIndex,      ///< frame index outside [0, kMaxFrameIndex]
};

/// Largest accepted frame index (2^53: every frame and window computation stays exact in
/// int64 and double).
inline constexpr FrameIndex kMaxFrameIndex = FrameIndex{1} << 53;

/// Human-readable name of a rejection.
const char* ToString(FrameRejection rejection);

}  // namespace mvtrack::tracker
