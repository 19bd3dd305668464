#pragma once
/// @file
/// Footprints against reference ground points that carry no identities (e.g. WILDTRACK's
/// ground-truth positions, or MVDeTr's merged ground points): per frame the number of points on
/// each side, the detection metrics (MODA, MODP, precision, recall) and the ground-plane
/// distance between the footprints and the points they are matched to. Stateless and pure: no
/// I/O, deterministic.

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "eval/sequence.h"

namespace mvtrack::eval {

/// How footprints and reference points are paired.
struct PointComparisonOptions {
  /// Gate, metres: a footprint and a reference point can be paired iff their ground-plane
  /// distance is <= gate. 0.5 m is the footprint radius of the WILDTRACK MOT evaluations.
  double gate_m = 0.5;
  /// Frames compared; empty = every frame of either sequence.
  std::vector<FrameRange> frame_ranges;
  /// The evaluated floor area, an axis-aligned rectangle [min_x, max_x] x [min_y, max_y] in
  /// metres: points of either side outside it are dropped before matching (and counted), as a
  /// dataset's annotations cover only its area. Empty = everywhere.
  struct Area {
    double min_x = 0.0;
    double max_x = 0.0;
    double min_y = 0.0;
    double max_y = 0.0;
  };
  std::optional<Area> area;

  /// Gate finite and > 0, frame ranges well-formed, area finite with min < max. On failure
  /// writes a reason to `why`.
  bool Validate(std::string* why) const;
};

/// One compared frame.
struct PointFrameCounts {
  FrameIndex frame = 0;
  std::int64_t num_reference = 0;  ///< reference points in this frame
  std::int64_t num_predicted = 0;  ///< predicted footprints in this frame
  std::int64_t num_matched = 0;    ///< pairs of the frame's assignment within the gate
};

/// Everything ComparePoints computes. Distances are NaN when nothing was matched.
struct PointComparison {
  bool valid = false;  ///< false: inputs or options rejected, see `error`
  std::string error;
  /// Human-readable statement of the protocol (pairing rule, gate, statistics, frames).
  std::string protocol;
  double gate_m = 0.0;
  std::vector<FrameRange> frame_ranges;
  std::optional<PointComparisonOptions::Area> area;
  /// Points dropped for lying outside `area` (reference / predicted), all compared frames.
  std::int64_t num_reference_outside = 0;
  std::int64_t num_predicted_outside = 0;
  /// Compared frames (union of both sides' frames in range), in increasing frame order.
  std::vector<PointFrameCounts> frames;
  std::int64_t num_reference = 0;  ///< reference points, all compared frames
  std::int64_t num_predicted = 0;  ///< predicted footprints, all compared frames
  std::int64_t num_matched = 0;    ///< matched pairs, all compared frames
  /// Frames whose predicted count equals the reference count.
  std::int64_t frames_with_equal_count = 0;
  /// Mean over frames of |num_predicted - num_reference|.
  double mean_abs_count_difference = std::numeric_limits<double>::quiet_NaN();
  /// Mean over frames of num_predicted - num_reference (positive: more footprints).
  double mean_count_difference = std::numeric_limits<double>::quiet_NaN();
  /// Largest |num_predicted - num_reference| of a frame.
  std::int64_t max_abs_count_difference = 0;
  /// num_matched / num_predicted and num_matched / num_reference.
  double precision = std::numeric_limits<double>::quiet_NaN();
  double recall = std::numeric_limits<double>::quiet_NaN();
  /// False positives (predicted - matched) and misses (reference - matched).
  std::int64_t false_positives = 0;
  std::int64_t misses = 0;
  /// MODA = 1 - (false_positives + misses) / num_reference (CLEAR, Kasturi et al. 2009, as
  /// MVDet's evaluation computes it; NaN without reference points).
  double moda = std::numeric_limits<double>::quiet_NaN();
  /// MODP as MVDet's evaluation computes it: the mean over matched pairs of 1 - d / gate (1 =
  /// every match exact). The mean matched distance in metres is mean_distance_m.
  double modp = std::numeric_limits<double>::quiet_NaN();
  /// Statistics of the matched pairs' ground-plane distances, metres: the median (mean of the
  /// two middle values for an even count), the mean, the 90th percentile (nearest rank:
  /// the ceil(0.9 n)-th smallest) and the largest.
  double median_distance_m = std::numeric_limits<double>::quiet_NaN();
  double mean_distance_m = std::numeric_limits<double>::quiet_NaN();
  double p90_distance_m = std::numeric_limits<double>::quiet_NaN();
  double max_distance_m = std::numeric_limits<double>::quiet_NaN();
};

/// Compares predicted footprints with reference points frame by frame. In every frame (the
/// union of both sides' frames within the ranges, increasing) the footprints and the points
/// are paired one-to-one by core::SolveAssignment on their ground-plane distances
/// (FootprintDistance) with the gate: the largest number of pairs first, then the least total
/// distance. Identities (ids) are ignored on both sides: each frame is matched afresh.
/// Joints are ignored. With an area, points of either side outside it are dropped first.
/// Both sequences must pass ValidateSequence (as "reference" and "predictions").
PointComparison ComparePoints(const EvalSequence& reference,
                              const EvalSequence& predictions,
                              const PointComparisonOptions& options);

}  // namespace mvtrack::eval
