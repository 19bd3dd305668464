#pragma once
/// @file
/// Rendering of evaluation results: a fixed-width text table for people and canonical JSON for
/// tools (sorted keys, fixed float precision, NaN as null). No JSON library, no I/O: both
/// return a std::string. Stateless.

#include <optional>
#include <string>

#include "eval/bone_lengths.h"
#include "eval/pcp.h"
#include "eval/point_comparison.h"
#include "eval/tracking_metrics.h"

namespace mvtrack::eval {

/// The results of one evaluation run; any part may be absent.
struct EvaluationReport {
  std::optional<TrackingEvaluation> tracking;
  std::optional<PcpResult> pcp;
  /// Footprints against reference points without identities (ComparePoints).
  std::optional<PointComparison> points;
  /// Bone-length stability of the predicted poses (EvaluateBoneLengths).
  std::optional<BoneLengthStability> bones;
};

/// A multi-line text table: CLEAR MOT / identity / MPJPE, then per-actor and per-group PCP,
/// then the point comparison (counts and distances), each followed by its protocol line. Ratios
/// print as percentages with 2 decimals, metres with 4 decimals, undefined values as "n/a". Ends
/// with a newline.
std::string FormatReportTable(const EvaluationReport& report);

/// The report as one JSON object, keys sorted at every level, numbers with exactly
/// `precision` decimals (clamped to [0, 17]; integers as integers), NaN and infinities as
/// null, 2-space indentation, newline-terminated. Top-level keys: "schema"
/// ("mvtrack.eval/1"), and "tracking" / "pcp" / "points" / "bones" when present. Ratios are
/// fractions (not %).
std::string ReportToJson(const EvaluationReport& report, int precision = 6);

}  // namespace mvtrack::eval
