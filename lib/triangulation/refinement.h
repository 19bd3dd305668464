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
#include <optional>
#include <string>
#include <vector>

#include "core/observation.h"
#include "geometry/camera_rig.h"

namespace mvtrack::triangulation {

/// Options of the per-window refinement (the tracker applies them in pose mode).
struct RefinementOptions {
  /// Two tracklets of one window whose PointDistance is at most this (metres) over at least
  /// min_duplicate_pairs common points are one person: their clusters are merged and
  /// triangulated together. Same-person duplicates on Shelf lie 0.03-0.10 m apart, different
  /// people >= 0.27 m (docs/ACCURACY.md). 0 disables merging.
  double merge_distance_m = 0.2;
  /// Pose mode: common (frame, point) pairs needed before PointDistance is trusted for a
  /// merge; >= 1.
  int min_duplicate_pairs = 10;
  /// Box mode: common frames needed before FootprintDistance is trusted for a merge; >= 1. A
  /// person split off its cluster for a few frames (a 2D track that broke and restarted) is
  /// still the same person.
  int box_min_duplicate_frames = 3;
  /// Box mode: two persons of one window whose FootprintDistance (median ground-plane distance
  /// over common frames) is at most this (metres) over at least min_duplicate_pairs common
  /// frames are one person that association split (a box clipped at the image border moves its
  /// centre, so on a ceiling grid PDNC's complete linkage splits people seen by many cameras):
  /// their clusters are merged and triangulated together. Must stay below the closest distance
  /// two people keep for a whole window (shoulder to shoulder about 0.45 m between body axes);
  /// 0 disables.
  double box_merge_distance_m = 0.3;
  /// Box mode: a triangulated box point lower than this above the floor
  /// (TrackerOptions::ground_height_m) is removed (RemovePointsOutsideHeights), and so is a
  /// person left without points. A box centre of a standing person lies about 0.5-1.2 m above
  /// the floor and a box bottom centre at it, so a point far below the floor or above 2 m is
  /// the crossing of rays of different people (a wrong cluster or a box clipped at the image
  /// border), not a person. Metres, finite, < box_max_height_m.
  double box_min_height_m = -0.3;
  /// Box mode: see box_min_height_m; the upper bound, metres above the floor, finite.
  double box_max_height_m = 2.0;
  /// Box mode with the top_bottom box points: the plausible heights of the bottom (feet)
  /// point above the floor, metres (finite, min < max). The feet of a detected person touch
  /// the floor (a few centimetres of triangulation error); where two cameras' rays of
  /// different people cross, their "feet" float or sink by a large fraction of the depth
  /// error. Points outside are removed like box_min_height_m's.
  double box_bottom_min_height_m = -0.4;
  /// See box_bottom_min_height_m.
  double box_bottom_max_height_m = 0.4;
  /// Box mode with the top_bottom box points: the plausible heights of the top (head) point
  /// above the floor, metres (finite, min < max): a child to a tall adult, with the detector's
  /// box padding.
  double box_top_min_height_m = 0.8;
  /// See box_top_min_height_m.
  double box_top_max_height_m = 2.4;
  /// Box mode: a tracklet of a person's cluster whose ReprojectionResidual against the person
  /// is above this (a fraction of its box scale |w + h|, the units of the association's lambda)
  /// shows somebody else: association's complete linkage put it there because in crowded top-
  /// down views many people lie near one epipolar line. Such tracklets are split off; the
  /// person is triangulated again from the rest (if they still span two cameras) and the
  /// split-off tracklets, if they span two cameras, become a person of their own (before
  /// duplicates are merged). Same-person tracklets reproject within about 0.1 (a box clipped at
  /// the image border moves its centre by more). 0 disables.
  double box_split_residual = 0.2;
  /// A person of one window whose footprint breaks the motion model (the state filtered up to
  /// a frame and the one filtered back from the next disagree by more than this squared
  /// Mahalanobis distance, with the linker's motion noise) is two people that association put
  /// into one cluster, one leaving while another arrives; the cluster is split there
  /// (tracker::ProcessWindowJob). Default: the 99.9 % quantile of chi-square with 4 degrees
  /// of freedom, the linker's gap gate. 0 disables. Finite, >= 0.
  double jump_gate_chi2 = 18.47;
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
  /// Temporal smoothing (SmoothTemporally), last step of the refinement: every point is
  /// replaced by the value at its own frame of a straight line fitted by weighted least squares
  /// to the same point's values in the tracklet's frames at most smooth_half_window frames
  /// away (tricube weights in the frame distance; at least 3 values, itself included, else the
  /// point is kept). A line, not a mean: a straight-line motion is kept exactly, also at the
  /// tracklet's ends where the frames lie on one side. Triangulation noise from two views is
  /// independent from frame to frame, so the fit averages it out; a limb's curved motion
  /// within +-3 frames (0.1 s) deviates from a line by millimetres. 0 disables smoothing.
  int smooth_half_window = 5;
  /// Smoothing changes only points that at most this many cameras observed at that frame
  /// (ObservingViews): two views give one triangulation, whose pixel noise goes straight into
  /// 3D; with three or more the candidate clustering has outvoted a bad view and the point is
  /// precise enough that a line would only cut the corners of fast motion. Points seen by more
  /// cameras still take part in their neighbours' fits. 0 smooths only points no camera observed
  /// (filled by completion); >= 0.
  int smooth_max_views = 2;
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
  /// Pose mode: after linking, every output frame's joints are fitted to the 2D keypoints of
  /// the views that see the person, with the bone lengths of its track (body::FitJoints,
  /// tracker::WindowFinalizer; docs/DECISIONS.md "Bodies"). Off by default until it is both
  /// better on every dataset and fast enough (measured in docs/ACCURACY.md "Bodies"): Campus at
  /// the hard level gains 0.3 PCP over seeds 2-10, Panoptic loses up to 2 mm MPJPE, and the pose
  /// grid's two-camera points run at a third of their speed with it (~35 µs per fit).
  bool fit_skeleton = false;

  /// Checks ranges: merge_distance_m and box_merge_distance_m finite and >= 0,
  /// box_min_height_m < box_max_height_m, both finite, box_split_residual finite and >= 0,
  /// min_duplicate_pairs >= 1,
  /// min_person_point_fraction in [0, 1], outlier_half_window >= 0, outlier_distance_m finite and >
  /// 0, smooth_half_window >= 0, smooth_max_views >= 0, max_fill_gap >= 0, fill_neighbors >= 1,
  /// min_points_to_fill >= 1. On failure sets `why` (if non-null) and returns false.
  bool Validate(std::string* why) const;
};

/// Mean Euclidean distance between the points of `a` and `b` with the same frame and the same
/// point index, over every such pair where both are present; `pairs` (if non-null) receives
/// their number. +infinity when there is none.
double PointDistance(const core::Tracklet3D& a,
                     const core::Tracklet3D& b,
                     std::int64_t* pairs = nullptr);

/// Median ground-plane distance between the footprints of `a` and `b` over their common frames:
/// a frame's footprint is the (x, y) of the mean of its present points (box mode: the one
/// point); frames where either has no point are skipped. The median (of an even count: the mean
/// of the two middle values) ignores the few frames where one of two coinciding persons is
/// triangulated far off. `frames` (if non-null) receives the number of frames compared.
/// +infinity when there is none. Deterministic.
double FootprintDistance(const core::Tracklet3D& a,
                         const core::Tracklet3D& b,
                         std::int64_t* frames = nullptr);

/// Removes every point of `tracklet` whose z is outside [min_z, max_z] (world frame, metres),
/// then every frame left without a point (a tracklet left without frames is empty). Returns the
/// number of points removed. Deterministic.
std::int64_t RemovePointsOutsideHeights(core::Tracklet3D* tracklet, double min_z, double max_z);

/// A closed interval of heights (world z, metres).
struct HeightRange {
  double min_z = 0.0;
  double max_z = 0.0;
};

/// As above with a range per point index (ranges[k] for point k; one for every point index of
/// the tracklet, checked).
std::int64_t RemovePointsOutsideHeights(core::Tracklet3D* tracklet,
                                        const std::vector<HeightRange>& ranges);

/// What TriangulateBoxEnds did.
struct BoxEndsStats {
  std::int64_t points = 0;              ///< end points triangulated (plausible)
  std::int64_t implausible_frames = 0;  ///< frames removed: an end had no plausible solution
};

/// Box mode (TrackerOptions::box_point center_ends): adds the box ends to a person whose
/// point 0 (the box centre) CMMT triangulated. Every row of `person` becomes
/// `first_point + ranges.size()` points long; at each frame, point first_point + e is
/// triangulated linearly (geometry::TriangulateTwoView, TriangulateLinear) from the observations of
/// `cluster` (indices into `tracklets`, one view per camera and frame) whose point first_point + e
/// is usable (confidence > 0 and >= min_confidence), when there are at least two. A solution behind
/// a camera or outside ranges[e] is not plausible; with three or more views each leave-one-out
/// subset is tried too, and the plausible solution with the smallest mean reprojection error is
/// kept. A frame where an end could be triangulated but had no plausible solution loses all its
/// points (the views disagree on where the person stands: rays of different people crossed), and
/// frames left without points are removed. Deterministic.
BoxEndsStats TriangulateBoxEnds(const geometry::CameraRig& rig,
                                const std::vector<core::Tracklet2D>& tracklets,
                                const std::vector<int>& cluster,
                                int first_point,
                                const std::vector<HeightRange>& ranges,
                                double min_confidence,
                                core::Tracklet3D* person);

/// How far `tracklet`'s observations are from where `person` projects in its camera: per frame
/// where both have points, the mean over points usable in the observation (confidence >=
/// min_confidence and > 0) and present in the person of |projection - observed| / scale_px
/// (undistorted pixels; a point behind the camera counts as +infinity; of an observation of a
/// cut box, Observation2D::cut_edges, the deviation's component past a cut edge does not count:
/// the person goes on out of the image there); the median over those
/// frames (of an even count: the mean of the two middle values). nullopt when no frame
/// compares. Only the first `max_points` points count (0: all). The tracklet's camera must be in
/// `rig` (checked). Deterministic.
std::optional<double> ReprojectionResidual(const geometry::CameraRig& rig,
                                           const core::Tracklet2D& tracklet,
                                           const core::Tracklet3D& person,
                                           double min_confidence,
                                           int max_points = 0);

/// The members of `cluster` (indices into `tracklets`, in cluster order) whose
/// ReprojectionResidual against `person` is above `max_residual`; members without a comparable
/// frame are kept (no evidence). Empty when max_residual is 0 (disabled). `max_points` as in
/// ReprojectionResidual.
std::vector<int> InconsistentTracklets(const geometry::CameraRig& rig,
                                       const std::vector<core::Tracklet2D>& tracklets,
                                       const std::vector<int>& cluster,
                                       const core::Tracklet3D& person,
                                       double max_residual,
                                       double min_confidence,
                                       int max_points = 0);

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
CompletionStats CompleteMissingPoints(core::Tracklet3D* tracklet, const RefinementOptions& options);

/// views[f][k] = how many distinct cameras among `cluster`'s tracklets (indices into
/// `tracklets`) observed point k at person.frames[f] (confidence > 0 and >= min_confidence).
/// One row per frame of `person`, one entry per point. Deterministic.
std::vector<std::vector<int>> ObservingViews(const std::vector<core::Tracklet2D>& tracklets,
                                             const std::vector<int>& cluster,
                                             const core::Tracklet3D& person,
                                             double min_confidence);

/// Smooths the points of `tracklet` over time (see RefinementOptions::smooth_half_window):
/// a point changes only when views[f][k] <= options.smooth_max_views (views as from
/// ObservingViews, one entry per frame and point; nullptr: every point may change). Each fit
/// uses the points as given, so the result does not depend on the order of the work. Missing
/// points stay missing. Returns the number of points changed. Every frame must have the same
/// number of points. Deterministic.
std::int64_t SmoothTemporally(core::Tracklet3D* tracklet,
                              const RefinementOptions& options,
                              const std::vector<std::vector<int>>* views = nullptr);

}  // namespace mvtrack::triangulation
