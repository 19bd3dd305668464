#pragma once
/// @file
/// HOTA, Higher Order Tracking Accuracy (Luiten et al., "HOTA: A Higher Order Metric for
/// Evaluating Multi-Object Tracking", IJCV 2021), with the definitions of TrackEval's reference
/// implementation (trackeval/metrics/hota.py): per localisation threshold alpha in {0.05,
/// 0.10, ..., 0.95}, a per-frame matching that maximises the global alignment score times the
/// similarity, then DetA = TP / (TP + FN + FP), AssA = mean over true positives of the Jaccard
/// index of their ids' trajectories, LocA = mean similarity of true positives, HOTA =
/// sqrt(DetA * AssA); the reported values are the means over alpha. The similarity of a
/// ground-truth object and a prediction at distance d is max(0, 1 - d / threshold), the
/// matching gate of the other metrics (TrackEval uses box IoU; tracks on a floor have no
/// boxes). Stateless and pure.

#include <cstdint>
#include <limits>
#include <vector>

#include "eval/sequence.h"

namespace mvtrack::eval {

/// HOTA and its sub-metrics, per alpha and averaged. Ratios in [0, 1].
struct HotaMetrics {
  /// The localisation thresholds: 0.05, 0.10, ..., 0.95 (19 values).
  std::vector<double> alphas;
  /// Per alpha (parallel to `alphas`).
  std::vector<std::int64_t> tp;
  std::vector<std::int64_t> fn;
  std::vector<std::int64_t> fp;
  std::vector<double> hota;
  std::vector<double> det_a;
  std::vector<double> ass_a;
  std::vector<double> det_re;
  std::vector<double> det_pr;
  std::vector<double> ass_re;
  std::vector<double> ass_pr;
  std::vector<double> loc_a;
  /// Means over alpha (TrackEval's summary values).
  double mean_hota = std::numeric_limits<double>::quiet_NaN();
  double mean_det_a = std::numeric_limits<double>::quiet_NaN();
  double mean_ass_a = std::numeric_limits<double>::quiet_NaN();
  double mean_loc_a = std::numeric_limits<double>::quiet_NaN();
};

/// HOTA of `predictions` against `ground_truth` over the frames in `ranges` (empty: all), with
/// similarity max(0, 1 - d / threshold_m) for `distance` (no distance: similarity 0). Both
/// sequences must be valid (ValidateSequencePair); threshold_m finite and > 0 (checked).
/// Like TrackEval, a sequence without predictions (or without ground truth) scores every
/// ground-truth object (prediction) as FN (FP) with LocA 1. O(frames * n^3) for the
/// per-frame assignments; memory O(distinct id pairs that ever overlap).
HotaMetrics EvaluateHota(const EvalSequence& ground_truth,
                         const EvalSequence& predictions,
                         DistanceKind distance,
                         double threshold_m,
                         const std::vector<FrameRange>& ranges);

}  // namespace mvtrack::eval
