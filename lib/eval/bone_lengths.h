#pragma once
/// @file
/// Bone-length stability of predicted 3D poses (issue 40): a body's limbs keep their length, so
/// per track the coefficient of variation of each limb's length over the track's frames
/// measures how much a tracker's skeletons breathe. Stateless, pure.

#include <cstdint>
#include <string>
#include <vector>

#include "core/keypoint_layout.h"
#include "eval/sequence.h"

namespace mvtrack::eval {

/// One track's limbs.
struct BoneLengthTrack {
  std::int64_t id = 0;
  int num_frames = 0;    ///< frames of the track in the evaluated ranges
  double cv_mean = 0.0;  ///< mean over its limbs of std / mean of the limb's length
  double cv_max = 0.0;   ///< the largest limb's
};

/// The stability of every track with at least `min_frames` frames.
struct BoneLengthStability {
  int min_frames = 0;
  std::vector<std::string> limbs;       ///< "l_shoulder-l_elbow", ...: those the layout has
  std::vector<BoneLengthTrack> tracks;  ///< by id
  double cv_mean = 0.0;                 ///< mean of the tracks' cv_mean (0 without tracks)
  double cv_worst_track = 0.0;          ///< largest cv_mean of a track
  double cv_max = 0.0;                  ///< largest cv_max of a track
  std::string protocol;
};

/// The 8 limbs (upper and lower arms and legs, both sides) of `layout` found by joint name,
/// over the frames of `predictions` in `frame_ranges` (all when empty). A limb is measured in
/// a frame when both its joints are present; a limb measured in fewer than 2 frames of a track
/// does not count. Tracks with fewer than `min_frames` frames are left out.
BoneLengthStability EvaluateBoneLengths(const EvalSequence& predictions,
                                        const core::KeypointLayout& layout,
                                        int min_frames,
                                        const std::vector<FrameRange>& frame_ranges = {});

}  // namespace mvtrack::eval
