#pragma once
/// @file
/// Multi-frame refinement of the short-term 3D tracklets of one sliding window, after CMMT:
///  - duplicate detection: two tracklets of one window whose common points coincide
///    (PointDistance) are one person that association split in two (typically a 2D detector
///    that split one person into two partial poses in some view, which the cannot-link rule
///    then keeps in different clusters); the tracker merges their clusters and triangulates
///    the union again;
///  - completion (CompleteMissingPoints): a joint that no camera pair could triangulate at a
///    frame (seen by one camera only, e.g. the far ear) is carried over from the nearest frames
///    of the same tracklet where it was triangulated, moved rigidly with its nearest
///    triangulated neighbours.
/// Stateless functions. Pure: no I/O, no globals.

#include <cstdint>
#include <string>

#include "core/observation.h"

namespace mvtrack::triangulation {

/// Options of the per-window refinement (the tracker applies them in pose mode).
struct RefinementOptions {
  /// Two tracklets of one window whose PointDistance is at most this (metres) over at least
  /// min_duplicate_pairs common points are one person: their clusters are merged and
  /// triangulated together. Same-person duplicates on Shelf lie 0.03-0.10 m apart, different
  /// people >= 0.27 m (docs/ACCURACY.md). 0 disables merging.
  double merge_distance_m = 0.2;
  /// Common (frame, point) pairs needed before PointDistance is trusted for a merge; >= 1.
  int min_duplicate_pairs = 10;
  /// A person (a window's 3D tracklet) whose best frame has fewer than this fraction of the
  /// layout's points triangulated is dropped: fragments of one or two joints from partial 2D
  /// detections are not people, and as tracks they steal identities (docs/ACCURACY.md). In
  /// [0, 1]; 0 keeps every person.
  double min_person_point_fraction = 0.25;
  /// Temporal outlier rejection: a triangulated point farther than outlier_distance_m from the
  /// component-wise median of the same point over the tracklet's frames within +-h frames,
  /// h = min(outlier_half_window, frames to the tracklet's first and last frame) (a symmetric
  /// window; at least 3 samples present, itself included; the first and last frame are never
  /// judged), is removed before completion (which may then refill it from its neighbours). The
  /// median of a straight-line motion is the point itself, so fast limbs are kept; an isolated
  /// wrong candidate cluster (another person's joint, a swapped side) is not. 0 disables
  /// rejection.
  int outlier_half_window = 3;
  /// See outlier_half_window; metres, finite, > 0.
  double outlier_distance_m = 0.2;
  /// Completion: a missing point is filled only from triangulated occurrences of the same
  /// point at most this many frames away (before and/or after). 0 disables completion.
  int max_fill_gap = 15;
  /// Completion: how many nearest triangulated neighbour points (in the reference frame)
  /// carry the missing point; with >= 3 spread-out neighbours the carry is rigid (rotation +
  /// translation, Kabsch), else a translation. >= 1.
  int fill_neighbors = 4;
  /// Completion: a frame needs at least this many triangulated points to be completed
  /// (a frame with fewer carries too little evidence of the body's pose); >= 1.
  int min_points_to_fill = 4;

  /// Checks ranges: merge_distance_m finite and >= 0, min_duplicate_pairs >= 1,
  /// min_person_point_fraction in [0, 1], outlier_half_window >= 0, outlier_distance_m finite and > 0,
  /// max_fill_gap >= 0, fill_neighbors >= 1, min_points_to_fill >= 1. On failure sets `why`
  /// (if non-null) and returns false.
  bool Validate(std::string* why) const;
};

/// Mean Euclidean distance between the points of `a` and `b` with the same frame and the same
/// point index, over every such pair where both are present; `pairs` (if non-null) receives
/// their number. +infinity when there is none.
double PointDistance(const core::Tracklet3D& a, const core::Tracklet3D& b,
                     std::int64_t* pairs = nullptr);

/// The largest number of points present in one frame of `tracklet` (0 when it has no frame).
int MaxPointsPerFrame(const core::Tracklet3D& tracklet);

/// Removes temporal outliers from `tracklet` (see RefinementOptions::outlier_half_window):
/// decisions use the points as given (removing one never changes another's median), so the
/// result does not depend on the order of the work. Returns the number of points removed.
/// Every frame must have the same number of points. Deterministic.
std::int64_t RejectTemporalOutliers(core::Tracklet3D* tracklet, const RefinementOptions& options);

/// Counts of one CompleteMissingPoints call.
struct CompletionStats {
  std::int64_t filled = 0;        ///< points filled
  std::int64_t filled_rigid = 0;  ///< of which carried by a rigid (Kabsch) fit
};

/// Fills missing points of `tracklet` (every frame must have the same number of points) from
/// the triangulated points of its other frames, per options (see RefinementOptions): at frame
/// t, a point k missing there is estimated from the nearest frame before and the nearest frame
/// after t (each at most max_fill_gap frames away) where k was triangulated: from reference
/// frame r, the fill_neighbors points nearest to k at r that are triangulated at both r and t
/// give the motion r -> t (rigid Kabsch fit with >= 3 neighbours that span a plane, else their
/// mean translation), which is applied to k at r. With both references the two estimates are
/// blended linearly in time. Only triangulated points are ever used as references (filled
/// points never feed other fills), so the result does not depend on the order of the work.
/// Frames with fewer than min_points_to_fill triangulated points, and tracklets with one
/// point per frame, are left as they are. Deterministic.
CompletionStats CompleteMissingPoints(core::Tracklet3D* tracklet,
                                      const RefinementOptions& options);

}  // namespace mvtrack::triangulation
