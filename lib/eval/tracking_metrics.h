#pragma once
/// @file
/// Tracking metrics of 3D tracks against ground truth, as the paper reports them (Sec.
/// "Experiments": MOTA, MOTP, FP, FN, IDs, MT, ML after Bernardin & Stiefelhagen 2008 and
/// Milan et al. 2016; IDF1 after Ristani et al. 2016), with the semantics of py-motmetrics
/// (MOTAccumulator.update and id_global_assignment) so numbers are comparable with published
/// ones; plus MPJPE over the matched pairs. Stateless and pure: no I/O, deterministic (objects
/// are processed in increasing id order, frames in increasing frame order).

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "eval/hota.h"
#include "eval/sequence.h"

namespace mvtrack::eval {

/// How ground truth and predictions are matched (one gate shared by CLEAR MOT and IDF1, as in
/// py-motmetrics, where both read the same distance matrices).
struct TrackingOptions {
  /// The distance used for matching.
  DistanceKind distance = DistanceKind::kFootprint;
  /// Gate for DistanceKind::kFootprint, metres: a pair can be matched iff distance <= gate.
  /// 0.5 m is the radius used for footprint MOTA/IDF1 on WILDTRACK (MVDet and successors).
  double footprint_threshold_m = 0.5;
  /// Gate for DistanceKind::kMeanJoint, metres (iff mean joint distance <= gate). 0.5 m is the
  /// mean-per-joint radius of VoxelPose's "recall@500mm" on Shelf/Campus.
  double mean_joint_threshold_m = 0.5;
  /// Frames evaluated; empty = every frame of either sequence.
  std::vector<FrameRange> frame_ranges;
  /// A predicted id "covers" a ground-truth person when CLEAR MOT matches the two in at least
  /// this many frames (IdentityCoverage): a few frames of a crossing do not count, half a
  /// second of a customer's visit (15 frames at 30 fps) does. >= 1.
  std::int64_t cover_min_frames = 15;
  /// A ground-truth person absent for more than this many frames (and present again) has
  /// returned (ReturnMetrics): 150 = 5 s at 30 fps, longer than any occlusion the trackers
  /// bridge, shorter than a visit to a fitting room. >= 1.
  std::int64_t return_min_gap_frames = 150;

  /// The gate of the selected distance.
  double threshold_m() const {
    return distance == DistanceKind::kFootprint ? footprint_threshold_m : mean_joint_threshold_m;
  }
  /// Gates finite and > 0, frame ranges well-formed. On failure writes a reason to `why`.
  bool Validate(std::string* why) const;
};

/// CLEAR MOT counts and scores. Ratios are NaN when their denominator is 0.
struct ClearMotMetrics {
  std::int64_t num_frames = 0;              ///< frames evaluated (union of both sides, in range)
  std::int64_t num_objects = 0;             ///< GT object-frames (the "GT" of MOTA)
  std::int64_t num_predictions = 0;         ///< predicted object-frames
  std::int64_t num_unique_objects = 0;      ///< distinct GT ids
  std::int64_t num_unique_predictions = 0;  ///< distinct predicted ids
  /// Matched pairs, switches included (TP; py-motmetrics calls this num_detections, its
  /// num_matches excludes the switches).
  std::int64_t num_matches = 0;
  std::int64_t num_false_positives = 0;  ///< FP: unmatched predicted object-frames
  std::int64_t num_misses = 0;           ///< FN: unmatched GT object-frames
  std::int64_t num_switches = 0;         ///< IDSW: GT matched to other id than its last match
  /// FM (py-motmetrics num_fragmentations): tracked -> missed transitions of a GT between its
  /// first and last matched frame.
  std::int64_t num_fragmentations = 0;
  std::int64_t mostly_tracked = 0;     ///< MT: GT matched in >= 80% of its frames
  std::int64_t partially_tracked = 0;  ///< PT: neither MT nor ML
  std::int64_t mostly_lost = 0;        ///< ML: GT matched in < 20% of its frames
  double total_distance_m = 0.0;       ///< sum of the matched pairs' distances
  /// MOTA = 1 - (FN + FP + IDSW) / num_objects.
  double mota = std::numeric_limits<double>::quiet_NaN();
  /// MOTP = total_distance_m / num_matches (metres; lower is better).
  double motp_m = std::numeric_limits<double>::quiet_NaN();
};

/// MT / PT / ML class of one GT trajectory.
enum class TrackCoverage { kMostlyTracked, kPartiallyTracked, kMostlyLost };

/// "MT", "PT" or "ML".
const char* TrackCoverageName(TrackCoverage coverage);

/// Per-GT-trajectory coverage.
struct ObjectCoverage {
  std::int64_t id = 0;              ///< GT id
  std::int64_t frames_present = 0;  ///< frames in which the GT object exists
  std::int64_t frames_matched = 0;  ///< of those, frames in which it was matched
  TrackCoverage coverage = TrackCoverage::kMostlyLost;
};

/// One identity switch (py-motmetrics SWITCH event).
struct IdSwitch {
  FrameIndex frame = 0;
  std::int64_t gt_id = 0;
  std::int64_t previous_prediction_id = 0;  ///< the GT's last matched prediction
  std::int64_t prediction_id = 0;           ///< the prediction it is matched to now
};

/// One GT trajectory <-> predicted trajectory pair of the global identity assignment.
struct IdentityMatch {
  std::int64_t gt_id = 0;
  std::int64_t prediction_id = 0;
  std::int64_t frames_within_gate = 0;  ///< IDTP contributed by this pair
};

/// Identity metrics (Ristani et al. 2016). Ratios are NaN when their denominator is 0.
struct IdentityMetrics {
  std::int64_t idtp = 0;  ///< object-frames where the GT is within the gate of its assigned track
  std::int64_t idfp = 0;  ///< predicted object-frames not counted as IDTP
  std::int64_t idfn = 0;  ///< GT object-frames not counted as IDTP
  double idp = std::numeric_limits<double>::quiet_NaN();  ///< IDTP / (IDTP + IDFP)
  double idr = std::numeric_limits<double>::quiet_NaN();  ///< IDTP / (IDTP + IDFN)
  /// 2 IDTP / (num_objects + num_predictions).
  double idf1 = std::numeric_limits<double>::quiet_NaN();
  /// Assigned pairs with at least one frame within the gate, sorted by GT id. (Pairs of the
  /// optimal padded assignment with no such frame contribute nothing and are omitted.)
  std::vector<IdentityMatch> matches;
};

/// Which ids cover which, from the CLEAR MOT matches (TrackingOptions::cover_min_frames): the
/// two ways identity fails that IDF1 blends into one number.
struct IdentityCoverage {
  /// A predicted id that covers more than one ground-truth person: the id passed from one
  /// person to another (the worst error for visit counts and dwell times).
  struct Transfer {
    std::int64_t prediction_id = 0;
    std::vector<std::int64_t> gt_ids;  ///< the persons it covers, in order of first match
  };
  /// A ground-truth person covered by more than one predicted id (the person was split).
  struct Fragmentation {
    std::int64_t gt_id = 0;
    std::vector<std::int64_t> prediction_ids;  ///< in order of first match
  };
  std::vector<Transfer> transfers;            ///< sorted by prediction id
  std::vector<Fragmentation> fragmentations;  ///< sorted by GT id
  std::int64_t cover_min_frames = 0;          ///< the option used
};

/// What happened to the ids of people who left and came back (re-identification): a person's
/// presence in the ground truth split at gaps of more than return_min_gap_frames frames into
/// visits; each visit after the first is a return. The id of a visit is the prediction CLEAR
/// MOT matched to the person in most of its frames (ties: the lowest id).
struct ReturnMetrics {
  enum class Outcome {
    kKept,           ///< the return's id is the previous visit's id
    kNewId,          ///< another id, never (>= cover_min_frames) anyone else's before
    kOtherPersonId,  ///< an id that covered another person before the return (the worst)
    kUntracked,      ///< the return or the previous visit was never matched
  };
  struct Return {
    std::int64_t gt_id = 0;
    FrameIndex frame = 0;         ///< first frame of the return
    std::int64_t gap_frames = 0;  ///< frames absent before it
    std::int64_t before_id = -1;  ///< id of the previous visit (-1: none matched)
    std::int64_t after_id = -1;   ///< id of the return (-1: none matched)
    Outcome outcome = Outcome::kUntracked;
  };
  std::int64_t min_gap_frames = 0;  ///< the option used
  std::int64_t returns = 0;
  std::int64_t kept = 0;
  std::int64_t new_id = 0;
  std::int64_t other_person_id = 0;
  std::int64_t untracked = 0;
  std::vector<Return> list;  ///< in (GT id, frame) order
};

/// "kept", "new id", "other person's id" or "untracked".
const char* ReturnOutcomeName(ReturnMetrics::Outcome outcome);

/// Joint position error over the CLEAR MOT matched pairs.
struct PoseErrorMetrics {
  std::int64_t num_pairs = 0;   ///< matched pairs with at least one joint valid in both
  std::int64_t num_joints = 0;  ///< joint errors averaged (joints valid in both, all pairs)
  /// MPJPE: mean over all (matched pair, joint valid in both) of ||p_j - g_j||, metres.
  double mpjpe_m = std::numeric_limits<double>::quiet_NaN();
  /// Per joint index: mean error (NaN where never valid in both) and number of samples.
  std::vector<double> per_joint_mpjpe_m;
  std::vector<std::int64_t> per_joint_count;
};

/// Everything EvaluateTracking computes.
struct TrackingEvaluation {
  bool valid = false;  ///< false: inputs or options rejected, see `error`; metrics are empty
  std::string error;
  /// Human-readable statement of the protocol (distance, gate, matching rules, frames).
  std::string protocol;
  DistanceKind distance = DistanceKind::kFootprint;
  double threshold_m = 0.0;
  std::vector<FrameRange> frame_ranges;
  ClearMotMetrics clear;
  IdentityMetrics identity;
  /// Id transfers and fragmentations (TrackingOptions::cover_min_frames).
  IdentityCoverage coverage;
  /// Returns of people who left and came back (TrackingOptions::return_min_gap_frames).
  ReturnMetrics returns;
  /// HOTA (eval/hota.h) with the same distance, gate (similarity 1 - d / gate) and frames.
  HotaMetrics hota;
  PoseErrorMetrics pose;
  std::vector<ObjectCoverage> objects;  ///< one per GT id, sorted by id
  std::vector<IdSwitch> switches;       ///< in frame order, then GT id order
};

/// Scores `predictions` against `ground_truth` (both in the same keypoint layout).
///
/// CLEAR MOT, frame by frame over the union of both sides' frames in increasing order, as
/// py-motmetrics' MOTAccumulator.update does: (1) every GT object, in increasing id order,
/// keeps the prediction it was last matched to (in any earlier frame) if that prediction is
/// present, not yet taken and within the gate; (2) the remaining GT objects and predictions are
/// matched by core::SolveAssignment on the distances with the gate (the largest number of
/// matches first, then the least total distance; py-motmetrics' expensive-edge
/// linear_sum_assignment has the same optimum); a step-2 match of a GT to a prediction other
/// than its last match is an identity switch. Unmatched GT objects are misses, unmatched
/// predictions false positives.
///
/// IDF1: the (n_gt + n_pred) square problem of py-motmetrics' id_global_assignment: GT i vs
/// track j costs IDFN + IDFP = (frames of i - c_ij) + (frames of j - c_ij), with c_ij the
/// frames in which both exist within the gate; GT i left unmatched costs its frames, track j
/// left unmatched its frames, dummy vs dummy 0. Solved exactly by core::SolveAssignment on a
/// fully finite matrix (see the .cc for why the off-diagonal dummy cells may carry the same
/// cost as the diagonal ones without changing the optimum).
///
/// Coverage: per (GT, prediction) pair the frames CLEAR MOT matched them (switches included);
/// a pair with at least cover_min_frames such frames counts.
///
/// O(frames * n^3) for the per-frame assignments plus O((n_ids)^3) for IDF1.
TrackingEvaluation EvaluateTracking(const EvalSequence& ground_truth,
                                    const EvalSequence& predictions,
                                    const TrackingOptions& options);

}  // namespace mvtrack::eval
