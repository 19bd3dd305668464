#include "eval/point_comparison.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <map>
#include <utility>

#include "core/linear_assignment.h"
#include "eval/number_format.h"

namespace mvtrack::eval {
namespace {

std::string Protocol(const PointComparisonOptions& options, std::int64_t num_frames) {
  std::string text;
  text += "Footprints vs reference points without identities: per frame, one-to-one ";
  text += "min-cost assignment on the ground-plane (x, y) distance, the most pairs first, then ";
  text += "the least total distance; a pair counts iff d <= " +
          internal::FormatFixed(options.gate_m, 3) + " m. ";
  text += "Distance statistics over the matched pairs of all frames (median: mean of the two ";
  text += "middle values for an even count; p90: nearest rank). ";
  text += "MODA = 1 - (FP + FN) / reference points; MODP = mean of 1 - d / gate over the pairs ";
  text += "(MVDet's evaluation), MODP[m] = mean matched distance. ";
  text += "Counts: per frame predicted vs reference points. ";
  if (options.area) {
    text += "Area: points of either side outside x in [" +
            internal::FormatFixed(options.area->min_x, 2) + ", " +
            internal::FormatFixed(options.area->max_x, 2) + "] m, y in [" +
            internal::FormatFixed(options.area->min_y, 2) + ", " +
            internal::FormatFixed(options.area->max_y, 2) + "] m are dropped before matching. ";
  } else {
    text += "Area: everywhere. ";
  }
  text += "Frames: " + DescribeFrameRanges(options.frame_ranges) + " (" +
          std::to_string(num_frames) + " compared: union of reference and prediction frames).";
  return text;
}

}  // namespace

bool PointComparisonOptions::Validate(std::string* why) const {
  if (!std::isfinite(gate_m) || gate_m <= 0.0) {
    if (why != nullptr) *why = "gate_m must be finite and > 0";
    return false;
  }
  if (area &&
      !(std::isfinite(area->min_x) && std::isfinite(area->max_x) && std::isfinite(area->min_y) &&
        std::isfinite(area->max_y) && area->min_x < area->max_x && area->min_y < area->max_y)) {
    if (why != nullptr) *why = "area must be finite with min < max on both axes";
    return false;
  }
  return ValidateFrameRanges(frame_ranges, why);
}

PointComparison ComparePoints(const EvalSequence& reference,
                              const EvalSequence& predictions,
                              const PointComparisonOptions& options) {
  PointComparison result;
  result.gate_m = options.gate_m;
  result.frame_ranges = options.frame_ranges;
  result.area = options.area;
  if (!options.Validate(&result.error)) {
    result.error = "point comparison options: " + result.error;
    return result;
  }
  if (!ValidateSequence(reference, "reference", &result.error) ||
      !ValidateSequence(predictions, "predictions", &result.error)) {
    return result;
  }

  // Union of both sides' frames inside the ranges, in increasing order.
  std::map<FrameIndex, std::pair<const EvalFrame*, const EvalFrame*>> by_frame;
  for (const EvalFrame& f : reference) {
    if (InFrameRanges(f.frame, options.frame_ranges)) by_frame[f.frame].first = &f;
  }
  for (const EvalFrame& f : predictions) {
    if (InFrameRanges(f.frame, options.frame_ranges)) by_frame[f.frame].second = &f;
  }

  const auto inside = [&](const EvalObject& o) {
    const PointComparisonOptions::Area& a = *options.area;
    return o.position.x() >= a.min_x && o.position.x() <= a.max_x && o.position.y() >= a.min_y &&
           o.position.y() <= a.max_y;
  };
  // The frame's objects of one side inside the area; `outside` counts the others.
  const auto kept = [&](const EvalFrame* frame, std::int64_t* outside) {
    std::vector<EvalObject> out;
    if (frame == nullptr) return out;
    for (const EvalObject& o : frame->objects) {
      if (!options.area || inside(o)) {
        out.push_back(o);
      } else {
        ++*outside;
      }
    }
    return out;
  };
  std::vector<double> distances;
  std::int64_t sum_abs_difference = 0;
  std::int64_t sum_difference = 0;
  for (const auto& [index, sides] : by_frame) {
    const std::vector<EvalObject> ref = kept(sides.first, &result.num_reference_outside);
    const std::vector<EvalObject> pred = kept(sides.second, &result.num_predicted_outside);
    Eigen::MatrixXd cost(static_cast<Eigen::Index>(ref.size()),
                         static_cast<Eigen::Index>(pred.size()));
    for (std::size_t r = 0; r < ref.size(); ++r) {
      for (std::size_t p = 0; p < pred.size(); ++p) {
        cost(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(p)) =
            FootprintDistance(ref[r], pred[p]);
      }
    }
    const core::Assignment assignment = core::SolveAssignment(cost, options.gate_m);
    PointFrameCounts counts;
    counts.frame = index;
    counts.num_reference = static_cast<std::int64_t>(ref.size());
    counts.num_predicted = static_cast<std::int64_t>(pred.size());
    for (const auto& [r, p] : assignment.matches) {
      const double d = cost(r, p);
      if (!(d <= options.gate_m)) continue;  // SolveAssignment never returns these; be explicit
      distances.push_back(d);
      ++counts.num_matched;
    }
    result.num_reference += counts.num_reference;
    result.num_predicted += counts.num_predicted;
    result.num_matched += counts.num_matched;
    const std::int64_t difference = counts.num_predicted - counts.num_reference;
    sum_difference += difference;
    sum_abs_difference += std::abs(difference);
    result.max_abs_count_difference =
        std::max(result.max_abs_count_difference, std::abs(difference));
    if (difference == 0) ++result.frames_with_equal_count;
    result.frames.push_back(counts);
  }

  const auto num_frames = static_cast<std::int64_t>(result.frames.size());
  if (num_frames > 0) {
    result.mean_abs_count_difference =
        static_cast<double>(sum_abs_difference) / static_cast<double>(num_frames);
    result.mean_count_difference =
        static_cast<double>(sum_difference) / static_cast<double>(num_frames);
  }
  if (result.num_predicted > 0) {
    result.precision =
        static_cast<double>(result.num_matched) / static_cast<double>(result.num_predicted);
  }
  if (result.num_reference > 0) {
    result.recall =
        static_cast<double>(result.num_matched) / static_cast<double>(result.num_reference);
  }
  result.false_positives = result.num_predicted - result.num_matched;
  result.misses = result.num_reference - result.num_matched;
  if (result.num_reference > 0) {
    result.moda = 1.0 - static_cast<double>(result.false_positives + result.misses) /
                            static_cast<double>(result.num_reference);
  }
  if (!distances.empty()) {
    double closeness = 0.0;
    for (const double d : distances) closeness += 1.0 - d / options.gate_m;
    result.modp = closeness / static_cast<double>(distances.size());
    std::sort(distances.begin(), distances.end());
    const std::size_t n = distances.size();
    result.median_distance_m =
        n % 2 == 1 ? distances[n / 2] : 0.5 * (distances[n / 2 - 1] + distances[n / 2]);
    double sum = 0.0;
    for (const double d : distances) sum += d;
    result.mean_distance_m = sum / static_cast<double>(n);
    // Nearest rank: the smallest k with k >= 0.9 n, i.e. ceil(9 n / 10), in integers.
    const std::size_t rank = (9 * n + 9) / 10;
    result.p90_distance_m = distances[std::max<std::size_t>(rank, 1) - 1];
    result.max_distance_m = distances.back();
  }
  result.protocol = Protocol(options, num_frames);
  result.valid = true;
  return result;
}

}  // namespace mvtrack::eval
