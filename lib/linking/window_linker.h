#pragma once
/// @file
/// Link Sliding Windows (paper Sec. "Link Sliding Windows", Eq. 8-9): the short-term 3D
/// tracklets U_{k,p} that each sliding window produces are linked into long-term 3D tracks by
/// an online track-to-track data association: Hungarian assignment (core::SolveAssignment,
/// Eq. 9) on the mean 3D distance over the frames two tracklets share (Eq. 8), with SORT-style
/// track management (birth, confirmation, death). Pure: no threads, no I/O, no clock.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/observation.h"
#include "core/types.h"

namespace mvtrack::linking {

/// WindowLinker settings. Frame-based quantities assume the window's frame indices (any rate).
struct LinkerOptions {
  /// Gate on the Eq. 8 distance, metres. A tracklet and a track whose overlapping parts are
  /// farther apart than this are never linked. In the overlap both tracklets are triangulated
  /// from (largely) the same 2D observations, so for the same person Eq. 8 only measures the
  /// disagreement of two triangulations (centimetres to ~0.2 m for box centres with CMMT
  /// infill), whereas two different people are at least a body width apart (shoulder width
  /// ~0.4-0.5 m, centre-to-centre distance rarely below 0.4 m even when passing). Swaps between
  /// close people are prevented by the optimal assignment, not by this gate; the gate only
  /// stops a tracklet from taking over a track it is clearly not. Finite, > 0.
  double max_link_distance_m = 0.5;
  /// Matched windows (the birth window counts as the first) before a track is confirmed; once
  /// confirmed it stays confirmed. 1 confirms at birth: a short-term 3D tracklet already is
  /// multi-frame, multi-view evidence (>= 2 cameras whose 2D tracklets agree epipolarly over a
  /// whole window, then robust triangulation), which is what SORT's min_hits buys for
  /// single-frame detections; every extra window would withhold delta frames of a new person.
  /// Must be >= 1.
  int min_hits = 1;
  /// A track unmatched for more than this many consecutive windows (skipped window ids
  /// included) dies. 2 windows (2 * delta = 40 frames, ~1.3 s at 30 fps) bridge a person that
  /// is seen by fewer than two cameras, or that PDNC fails to cluster, for one or two windows,
  /// while the gap gate after two missed windows (0.5 + 0.15 * 31 = 5.15 m for nu = 30,
  /// delta = 20) is still bounded. Must be >= 0.
  int max_missed_windows = 2;
  /// Maximum speed used to gate links across a gap (no overlapping frames with a common
  /// point): the centroid distance must satisfy d <= max_link_distance_m +
  /// max_speed_m_per_frame * gap_frames. 0.15 m/frame is 4.5 m/s at 30 fps (a running person),
  /// an upper bound rather than a typical speed. Finite, >= 0.
  double max_speed_m_per_frame = 0.15;

  /// Checks the ranges above; on failure writes a reason to `why` (if not null).
  bool Validate(std::string* why) const;
};

/// Life-cycle state of a long-term track (SORT-style track management).
enum class TrackState {
  kTentative,  ///< matched in its latest window, fewer than min_hits matched windows so far
  kConfirmed,  ///< matched in its latest window, at least min_hits matched windows
  kLost,       ///< missed >= 1 window, still alive (confirmed or not: compare hits to min_hits)
};

/// One alive long-term 3D track.
struct LinkedTrack {
  /// Unique per WindowLinker, starts at 1, never reused.
  TrackId3D id = 0;
  /// Derived after every Link: kLost when missed_windows > 0, else kConfirmed when
  /// hits >= min_hits, else kTentative.
  TrackState state = TrackState::kTentative;
  /// Windows in which a tracklet was linked to it (including the birth window).
  int hits = 0;
  /// Consecutive windows (skipped window ids included) without a linked tracklet.
  int missed_windows = 0;
  /// Window of birth.
  std::int64_t first_window = 0;
  /// Last window in which a tracklet was linked to it (or its birth window).
  std::int64_t last_window = 0;
  /// The most recent short-term tracklet linked to it.
  core::Tracklet3D last_tracklet;
};

/// How an input tracklet was linked.
enum class LinkKind {
  kBirth,    ///< unmatched: started a new track
  kOverlap,  ///< linked on the Eq. 8 distance over overlapping frames
  kGap,      ///< linked across a gap with the centroid distance (gap rule)
};

/// The outcome of WindowLinker::Link for one window.
struct LinkResult {
  /// The window_id passed to Link.
  std::int64_t window_id = 0;
  /// Parallel to the input tracklets: the long-term id each was linked to (new ids for births).
  std::vector<TrackId3D> track_of_tracklet;
  /// Tracks started in this window (sorted ascending).
  std::vector<TrackId3D> born;
  /// Tracks that died in this window, including through skipped window ids (sorted ascending).
  std::vector<TrackId3D> died;
  /// Parallel to the input: for kOverlap the Eq. 8 distance to the linked track, for kGap the
  /// centroid distance of the gap rule (metres), NaN for births.
  std::vector<double> link_distance_m;
  /// Parallel to the input: how each tracklet was linked.
  std::vector<LinkKind> link_kind;
};

/// Eq. 8 distance between two 3D tracklets: per overlapping frame the mean over points valid
/// in both (same point index; a point is valid when present and finite) of ||X_m - X_n||, then
/// the mean over the overlapping frames that have at least one common valid point. nullopt when
/// there is no such frame. Stateless. Both tracklets must be well formed (frames strictly
/// increasing, points parallel to frames; checked).
std::optional<double> MeanOverlapDistance(const core::Tracklet3D& a, const core::Tracklet3D& b);

/// The gap rule's measurement between an earlier tracklet `from` and a later tracklet `to` that
/// share no frame with a common valid point.
struct GapMeasurement {
  /// Distance between the centroids of the points of `from`'s last frame with a valid point and
  /// of `to`'s first frame with a valid point, metres. Both centroids are taken over the point
  /// indices valid in both frames when there is at least one, otherwise over each frame's own
  /// valid points (pose mode: comparing different joint subsets would bias the distance).
  double distance_m = 0.0;
  /// |to's first valid frame - from's last valid frame|, frames.
  std::int64_t gap_frames = 0;
};

/// The gap-rule measurement from `from` to `to`; nullopt when either has no valid point.
/// Stateless. Both tracklets must be well formed (checked).
std::optional<GapMeasurement> MeasureGap(const core::Tracklet3D& from, const core::Tracklet3D& to);

/// Online track-to-track data association across sliding windows (paper Sec. "Link Sliding
/// Windows", Eq. 8-9, track management after SORT, Bewley et al. 2016).
///
/// Per window, with the alive tracks as rows and the window's tracklets as columns:
///  1. Overlap stage: cost = Eq. 8 distance between the track's last tracklet and the tracklet
///     (MeanOverlapDistance), pairs without it or above max_link_distance_m forbidden; solved
///     with core::SolveAssignment (Eq. 9).
///  2. Gap stage, among the tracks and tracklets left unmatched by stage 1: pairs WITHOUT an
///     Eq. 8 distance (no common frame with a common valid point, e.g. a track that missed
///     windows) cost the MeasureGap centroid distance, forbidden above
///     max_link_distance_m + max_speed_m_per_frame * gap_frames; solved again.
///  Overlap matches come first because Eq. 8 averages many frames and points over the same
///  time span, while the gap rule compares two single frames across a gap with a loose,
///  speed-based gate; and because SolveAssignment maximises the number of matches before the
///  cost, one joint matrix could drop a good overlap match to make room for a gap match.
///  3. Matched tracks take the tracklet (hits + 1, missed = 0); each unmatched tracklet starts a
///     track with a fresh id (in input order); each unmatched track misses the window and dies
///     when missed_windows > max_missed_windows.
///
/// Single-owner, single-threaded; deterministic (ties go to the lowest track id, then the lowest
/// tracklet index).
class WindowLinker {
 public:
  /// `options` must be valid (checked; validate configuration beforehand).
  explicit WindowLinker(LinkerOptions options = {});

  /// Links the next window's tracklets. Window ids must be strictly increasing (checked); a
  /// skipped id counts as a window with no tracklets (its misses are applied, and tracks that
  /// die of them are reported in this result, before linking). Tracklets must be well formed
  /// (checked); a tracklet without any valid point cannot be linked and is born.
  LinkResult Link(std::int64_t window_id, const std::vector<core::Tracklet3D>& tracklets);

  /// Alive tracks sorted by id.
  const std::vector<LinkedTrack>& tracks() const { return tracks_; }

  /// The options in use.
  const LinkerOptions& options() const { return options_; }

 private:
  TrackState StateOf(const LinkedTrack& track) const;

  LinkerOptions options_;
  std::vector<LinkedTrack> tracks_;  // increasing id order
  std::optional<std::int64_t> last_window_;
  TrackId3D next_id_ = 1;
};

}  // namespace mvtrack::linking
