#include "eval/tracking_metrics.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <optional>
#include <utility>

#include "core/linear_assignment.h"
#include "eval/number_format.h"

namespace mvtrack::eval {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
using internal::kNaN;
using internal::Ratio;

std::string Protocol(const TrackingOptions& options, std::int64_t num_frames) {
  std::string text;
  text += "CLEAR MOT (Bernardin & Stiefelhagen 2008) with py-motmetrics semantics: per frame, ";
  text += "each GT keeps the prediction it was last matched to if that pair is within the gate, ";
  text += "the rest are matched by min-cost assignment maximising the number of matches first; ";
  text += "IDSW = GT matched to another prediction than its last match; ";
  text += "MOTA = 1 - (FN + FP + IDSW) / GT; ";
  text += "MOTP = mean matched distance (m); MT >= 80%, ML < 20% of a GT's frames matched. ";
  text += "IDF1/IDP/IDR (Ristani et al. 2016): global min-cost assignment of GT to predicted ";
  text += "trajectories on the padded (n_gt + n_pred) square problem, same gate. ";
  text += "MPJPE: mean joint error over the CLEAR MOT matched pairs, joints valid in both. ";
  text += "IDTR (id transfers) = predicted ids covering >= 2 GT persons, IDFRAG = GT persons ";
  text += "covered by >= 2 predicted ids, where an id covers a person when CLEAR MOT matched ";
  text += "them in >= " + std::to_string(options.cover_min_frames) + " frames. ";
  text += "Returns: a GT person absent for > " + std::to_string(options.return_min_gap_frames) +
          " frames and present again; the id of a visit is the one CLEAR MOT matched in most of "
          "its frames; kept = the previous visit's id, another person's id = an id that covered "
          "another person before the return. ";
  text += "HOTA (Luiten et al. 2021, TrackEval's definitions): mean over alpha = 0.05..0.95 of ";
  text += "sqrt(DetA * AssA), similarity max(0, 1 - d / gate); DetA, AssA, LocA likewise. ";
  text += "Distance: ";
  text += DistanceKindName(options.distance);
  text += ", match iff d <= " + internal::FormatFixed(options.threshold_m(), 3) + " m. ";
  text += "Frames: " + DescribeFrameRanges(options.frame_ranges) + " (" +
          std::to_string(num_frames) + " evaluated: union of GT and prediction frames).";
  return text;
}

// Per-GT bookkeeping for MT/PT/ML and fragmentations.
struct GtHistory {
  std::int64_t present = 0;
  std::int64_t matched = 0;
  // Matched flag of each frame the object is present in, in frame order.
  std::vector<bool> matched_when_present;
};

std::int64_t Fragmentations(const std::vector<bool>& matched) {
  // py-motmetrics num_fragmentations: within [first matched, last matched], count the starts of
  // runs of misses.
  const auto first = std::find(matched.begin(), matched.end(), true);
  if (first == matched.end()) return 0;
  const auto last = std::find(matched.rbegin(), matched.rend(), true).base();  // one past
  std::int64_t count = 0;
  for (auto it = first + 1; it < last; ++it) {
    if (!*it && *(it - 1)) ++count;
  }
  return count;
}

TrackCoverage Classify(std::int64_t matched, std::int64_t present) {
  // Integer forms of matched / present >= 0.8 and < 0.2 (no rounding at the boundaries).
  if (5 * matched >= 4 * present) return TrackCoverage::kMostlyTracked;
  if (5 * matched < present) return TrackCoverage::kMostlyLost;
  return TrackCoverage::kPartiallyTracked;
}

}  // namespace

bool TrackingOptions::Validate(std::string* why) const {
  const auto fail = [why](const std::string& text) {
    if (why != nullptr) *why = text;
    return false;
  };
  if (!std::isfinite(footprint_threshold_m) || footprint_threshold_m <= 0.0) {
    return fail("footprint_threshold_m must be finite and > 0");
  }
  if (!std::isfinite(mean_joint_threshold_m) || mean_joint_threshold_m <= 0.0) {
    return fail("mean_joint_threshold_m must be finite and > 0");
  }
  if (cover_min_frames < 1) return fail("cover_min_frames must be >= 1");
  if (return_min_gap_frames < 1) return fail("return_min_gap_frames must be >= 1");
  return ValidateFrameRanges(frame_ranges, why);
}

const char* ReturnOutcomeName(ReturnMetrics::Outcome outcome) {
  switch (outcome) {
    case ReturnMetrics::Outcome::kKept:
      return "kept";
    case ReturnMetrics::Outcome::kNewId:
      return "new id";
    case ReturnMetrics::Outcome::kOtherPersonId:
      return "other person's id";
    case ReturnMetrics::Outcome::kUntracked:
      return "untracked";
  }
  return "unknown";
}

const char* TrackCoverageName(TrackCoverage coverage) {
  switch (coverage) {
    case TrackCoverage::kMostlyTracked:
      return "MT";
    case TrackCoverage::kPartiallyTracked:
      return "PT";
    case TrackCoverage::kMostlyLost:
      return "ML";
  }
  return "?";
}

TrackingEvaluation EvaluateTracking(const EvalSequence& ground_truth,
                                    const EvalSequence& predictions,
                                    const TrackingOptions& options) {
  TrackingEvaluation result;
  result.distance = options.distance;
  result.threshold_m = options.threshold_m();
  result.frame_ranges = options.frame_ranges;
  if (!options.Validate(&result.error)) {
    result.error = "tracking options: " + result.error;
    return result;
  }
  int num_joints = 0;
  if (!ValidateSequencePair(ground_truth, predictions, &result.error, &num_joints)) return result;

  const double gate = options.threshold_m();
  const std::vector<AlignedFrame> frames =
      AlignFrames(ground_truth, predictions, options.frame_ranges);

  ClearMotMetrics& clear = result.clear;
  PoseErrorMetrics& pose = result.pose;
  pose.per_joint_count.assign(static_cast<std::size_t>(num_joints), 0);
  std::vector<double> per_joint_sum(static_cast<std::size_t>(num_joints), 0.0);
  double joint_error_sum = 0.0;

  std::map<std::int64_t, GtHistory> gt_history;
  std::map<std::int64_t, std::int64_t> pred_frames;
  // py-motmetrics `m`: the prediction each GT was last matched to.
  std::map<std::int64_t, std::int64_t> last_match;
  // c_ij of the identity measures: frames where GT i and prediction j are within the gate.
  std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> frames_within_gate;
  // Coverage: frames CLEAR MOT matched GT i and prediction j, and the frame of their first match.
  std::map<std::pair<std::int64_t, std::int64_t>, std::pair<std::int64_t, FrameIndex>> matched;
  // Returns: per GT, its frames with the matched prediction (-1: missed); per prediction, the
  // frames it was matched in with the GT.
  std::map<std::int64_t, std::vector<std::pair<FrameIndex, std::int64_t>>> gt_frames;
  std::map<std::int64_t, std::vector<std::pair<FrameIndex, std::int64_t>>> pred_matches;

  for (const AlignedFrame& f : frames) {
    ++clear.num_frames;
    const std::size_t n_gt = f.gt.size();
    const std::size_t n_pred = f.pred.size();
    clear.num_objects += static_cast<std::int64_t>(n_gt);
    clear.num_predictions += static_cast<std::int64_t>(n_pred);
    for (const EvalObject* p : f.pred) ++pred_frames[p->id];

    // Gated distances: +inf where the pair can never be matched in this frame.
    Eigen::MatrixXd dist = Eigen::MatrixXd::Constant(
        static_cast<Eigen::Index>(n_gt), static_cast<Eigen::Index>(n_pred), kInf);
    for (std::size_t i = 0; i < n_gt; ++i) {
      for (std::size_t j = 0; j < n_pred; ++j) {
        const std::optional<double> d = ObjectDistance(options.distance, *f.gt[i], *f.pred[j]);
        if (d.has_value() && *d <= gate) {
          dist(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = *d;
          ++frames_within_gate[{f.gt[i]->id, f.pred[j]->id}];
        }
      }
    }

    std::vector<int> pred_of_gt(n_gt, -1);
    std::vector<char> pred_taken(n_pred, 0);

    // Step 1: keep last correspondences that are still within the gate.
    for (std::size_t i = 0; i < n_gt; ++i) {
      const auto last = last_match.find(f.gt[i]->id);
      if (last == last_match.end()) continue;
      for (std::size_t j = 0; j < n_pred; ++j) {
        if (pred_taken[j] || f.pred[j]->id != last->second) continue;
        if (std::isfinite(dist(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)))) {
          pred_of_gt[i] = static_cast<int>(j);
          pred_taken[j] = 1;
        }
        break;
      }
    }

    // Step 2: optimal assignment of the rest (rows/columns taken in step 1 are forbidden).
    Eigen::MatrixXd rest = dist;
    for (std::size_t i = 0; i < n_gt; ++i) {
      if (pred_of_gt[i] >= 0) rest.row(static_cast<Eigen::Index>(i)).setConstant(kInf);
    }
    for (std::size_t j = 0; j < n_pred; ++j) {
      if (pred_taken[j]) rest.col(static_cast<Eigen::Index>(j)).setConstant(kInf);
    }
    const core::Assignment assignment = core::SolveAssignment(rest, gate);
    for (const auto& [row, col] : assignment.matches) {
      const auto i = static_cast<std::size_t>(row);
      const auto j = static_cast<std::size_t>(col);
      const std::int64_t gt_id = f.gt[i]->id;
      const std::int64_t pred_id = f.pred[j]->id;
      const auto last = last_match.find(gt_id);
      if (last != last_match.end() && last->second != pred_id) {
        ++clear.num_switches;
        result.switches.push_back({f.frame, gt_id, last->second, pred_id});
      }
      pred_of_gt[i] = col;
      pred_taken[j] = 1;
    }

    // Bookkeeping of this frame's matches, misses and false positives.
    std::int64_t matches = 0;
    for (std::size_t i = 0; i < n_gt; ++i) {
      const EvalObject& g = *f.gt[i];
      GtHistory& history = gt_history[g.id];
      ++history.present;
      const int j = pred_of_gt[i];
      history.matched_when_present.push_back(j >= 0);
      gt_frames[g.id].emplace_back(f.frame, j < 0 ? -1 : f.pred[static_cast<std::size_t>(j)]->id);
      if (j < 0) continue;
      pred_matches[f.pred[static_cast<std::size_t>(j)]->id].emplace_back(f.frame, g.id);
      ++history.matched;
      ++matches;
      const EvalObject& p = *f.pred[static_cast<std::size_t>(j)];
      last_match[g.id] = p.id;
      auto m = matched.try_emplace({g.id, p.id}, 0, f.frame).first;
      ++m->second.first;
      clear.total_distance_m += dist(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
      bool any_joint = false;
      for (std::size_t k = 0; k < static_cast<std::size_t>(num_joints); ++k) {
        if (!g.joints[k].has_value() || !p.joints[k].has_value()) continue;
        const double e = (*g.joints[k] - *p.joints[k]).norm();
        per_joint_sum[k] += e;
        ++pose.per_joint_count[k];
        joint_error_sum += e;
        ++pose.num_joints;
        any_joint = true;
      }
      if (any_joint) ++pose.num_pairs;
    }
    clear.num_matches += matches;
    clear.num_misses += static_cast<std::int64_t>(n_gt) - matches;
    clear.num_false_positives += static_cast<std::int64_t>(n_pred) - matches;
  }

  // CLEAR MOT summary.
  clear.num_unique_objects = static_cast<std::int64_t>(gt_history.size());
  clear.num_unique_predictions = static_cast<std::int64_t>(pred_frames.size());
  for (const auto& [id, history] : gt_history) {
    const TrackCoverage coverage = Classify(history.matched, history.present);
    result.objects.push_back({id, history.present, history.matched, coverage});
    if (coverage == TrackCoverage::kMostlyTracked) ++clear.mostly_tracked;
    if (coverage == TrackCoverage::kPartiallyTracked) ++clear.partially_tracked;
    if (coverage == TrackCoverage::kMostlyLost) ++clear.mostly_lost;
    clear.num_fragmentations += Fragmentations(history.matched_when_present);
  }
  if (clear.num_objects > 0) {
    clear.mota = 1.0 - static_cast<double>(clear.num_misses + clear.num_false_positives +
                                           clear.num_switches) /
                           static_cast<double>(clear.num_objects);
  }
  if (clear.num_matches > 0) {
    clear.motp_m = clear.total_distance_m / static_cast<double>(clear.num_matches);
  }

  // MPJPE summary.
  if (pose.num_joints > 0) pose.mpjpe_m = joint_error_sum / static_cast<double>(pose.num_joints);
  pose.per_joint_mpjpe_m.assign(static_cast<std::size_t>(num_joints), kNaN);
  for (std::size_t k = 0; k < static_cast<std::size_t>(num_joints); ++k) {
    if (pose.per_joint_count[k] > 0) {
      pose.per_joint_mpjpe_m[k] = per_joint_sum[k] / static_cast<double>(pose.per_joint_count[k]);
    }
  }

  // Identity measures: py-motmetrics id_global_assignment. Rows: GT 0..no-1, then one dummy row
  // per prediction; columns: predictions 0..nh-1, then one dummy column per GT.
  //   GT i  x prediction j : (frames_i - c_ij) + (frames_j - c_ij)   IDFN + IDFP
  //   GT i  x dummy column : frames_i                                 GT unmatched: all IDFN
  //   dummy x prediction j : frames_j                                 track unmatched: all IDFP
  //   dummy x dummy        : 0
  // py-motmetrics forbids (NaN) the off-diagonal dummy cells, i.e. GT i may only take dummy
  // column i. Here every cell is finite, GT i costs frames_i with any dummy column (and
  // prediction j frames_j with any dummy row): every perfect matching then costs
  // sum_{matched (i,j)} (frames_i + frames_j - 2 c_ij) + sum_{unmatched i} frames_i +
  // sum_{unmatched j} frames_j, exactly the cost of the py-motmetrics matching with the same
  // GT-prediction pairs, so both problems have the same optimum. On a fully finite square
  // matrix with an infinite gate core::SolveAssignment is a plain min-cost perfect assignment.
  // The optimum maximises IDTP = sum c_ij over the matched pairs, since the cost equals
  // num_objects + num_predictions - 2 IDTP.
  {
    std::vector<std::int64_t> gt_ids;
    std::vector<std::int64_t> gt_counts;
    for (const auto& [id, history] : gt_history) {
      gt_ids.push_back(id);
      gt_counts.push_back(history.present);
    }
    std::vector<std::int64_t> pred_ids;
    std::vector<std::int64_t> pred_counts;
    for (const auto& [id, count] : pred_frames) {
      pred_ids.push_back(id);
      pred_counts.push_back(count);
    }
    const Eigen::Index no = static_cast<Eigen::Index>(gt_ids.size());
    const Eigen::Index nh = static_cast<Eigen::Index>(pred_ids.size());
    std::map<std::int64_t, Eigen::Index> pred_index;
    for (Eigen::Index j = 0; j < nh; ++j) pred_index[pred_ids[static_cast<std::size_t>(j)]] = j;
    std::map<std::int64_t, Eigen::Index> gt_index;
    for (Eigen::Index i = 0; i < no; ++i) gt_index[gt_ids[static_cast<std::size_t>(i)]] = i;

    using CountMatrix = Eigen::Matrix<std::int64_t, Eigen::Dynamic, Eigen::Dynamic>;
    CountMatrix within = CountMatrix::Zero(no, nh);
    for (const auto& [pair, count] : frames_within_gate) {
      within(gt_index.at(pair.first), pred_index.at(pair.second)) = count;
    }
    Eigen::MatrixXd cost = Eigen::MatrixXd::Zero(no + nh, nh + no);
    for (Eigen::Index i = 0; i < no; ++i) {
      const auto fi = static_cast<double>(gt_counts[static_cast<std::size_t>(i)]);
      for (Eigen::Index j = 0; j < nh; ++j) {
        const auto fj = static_cast<double>(pred_counts[static_cast<std::size_t>(j)]);
        cost(i, j) = fi + fj - 2.0 * static_cast<double>(within(i, j));
      }
      cost.block(i, nh, 1, no).setConstant(fi);
    }
    for (Eigen::Index j = 0; j < nh; ++j) {
      const auto fj = static_cast<double>(pred_counts[static_cast<std::size_t>(j)]);
      cost.block(no, j, nh, 1).setConstant(fj);
    }
    IdentityMetrics& identity = result.identity;
    if (no + nh > 0) {
      const core::Assignment assignment =
          core::SolveAssignment(cost, std::numeric_limits<double>::max());
      for (const auto& [row, col] : assignment.matches) {
        if (row >= no || col >= nh) continue;
        const std::int64_t c = within(row, col);
        if (c == 0) continue;
        identity.idtp += c;
        identity.matches.push_back(
            {gt_ids[static_cast<std::size_t>(row)], pred_ids[static_cast<std::size_t>(col)], c});
      }
    }
    identity.idfn = clear.num_objects - identity.idtp;
    identity.idfp = clear.num_predictions - identity.idtp;
    identity.idp = Ratio(identity.idtp, identity.idtp + identity.idfp);
    identity.idr = Ratio(identity.idtp, identity.idtp + identity.idfn);
    identity.idf1 = Ratio(2 * identity.idtp, clear.num_objects + clear.num_predictions);
  }

  // Coverage: transfers and fragmentations.
  {
    IdentityCoverage& cov = result.coverage;
    cov.cover_min_frames = options.cover_min_frames;
    // (first match frame, other id) per id, for the order of first match.
    std::map<std::int64_t, std::vector<std::pair<FrameIndex, std::int64_t>>> gts_of_pred;
    std::map<std::int64_t, std::vector<std::pair<FrameIndex, std::int64_t>>> preds_of_gt;
    for (const auto& [ids, count_first] : matched) {
      if (count_first.first < options.cover_min_frames) continue;
      gts_of_pred[ids.second].emplace_back(count_first.second, ids.first);
      preds_of_gt[ids.first].emplace_back(count_first.second, ids.second);
    }
    for (auto& [pred, list] : gts_of_pred) {
      if (list.size() < 2) continue;
      std::sort(list.begin(), list.end());
      IdentityCoverage::Transfer t;
      t.prediction_id = pred;
      for (const auto& [frame, gt] : list) t.gt_ids.push_back(gt);
      cov.transfers.push_back(std::move(t));
    }
    for (auto& [gt, list] : preds_of_gt) {
      if (list.size() < 2) continue;
      std::sort(list.begin(), list.end());
      IdentityCoverage::Fragmentation fr;
      fr.gt_id = gt;
      for (const auto& [frame, pred] : list) fr.prediction_ids.push_back(pred);
      cov.fragmentations.push_back(std::move(fr));
    }
  }
  // Returns.
  {
    ReturnMetrics& ret = result.returns;
    ret.min_gap_frames = options.return_min_gap_frames;
    // The id matched in most frames of [b, e) of `frames` (ties: lowest), -1 if none.
    const auto dominant = [](const std::vector<std::pair<FrameIndex, std::int64_t>>& visits,
                             std::size_t b,
                             std::size_t e) {
      std::map<std::int64_t, std::int64_t> count;
      for (std::size_t k = b; k < e; ++k) {
        if (visits[k].second >= 0) ++count[visits[k].second];
      }
      std::int64_t best = -1, best_count = 0;
      for (const auto& [id, c] : count) {
        if (c > best_count) {
          best = id;
          best_count = c;
        }
      }
      return best;
    };
    for (const auto& [gt, seen] : gt_frames) {
      std::size_t visit_begin = 0;
      std::int64_t previous_id = -1;
      for (std::size_t k = 1; k <= seen.size(); ++k) {
        const bool split = k == seen.size() ||
                           seen[k].first - seen[k - 1].first - 1 > options.return_min_gap_frames;
        if (!split) continue;
        const std::int64_t id = dominant(seen, visit_begin, k);
        if (visit_begin > 0) {
          ReturnMetrics::Return r;
          r.gt_id = gt;
          r.frame = seen[visit_begin].first;
          r.gap_frames = seen[visit_begin].first - seen[visit_begin - 1].first - 1;
          r.before_id = previous_id;
          r.after_id = id;
          if (id < 0 || previous_id < 0) {
            r.outcome = ReturnMetrics::Outcome::kUntracked;
          } else if (id == previous_id) {
            r.outcome = ReturnMetrics::Outcome::kKept;
          } else {
            // Did the return's id cover someone else before the return?
            std::map<std::int64_t, std::int64_t> others;
            bool other = false;
            for (const auto& [frame, other_gt] : pred_matches[id]) {
              if (frame >= r.frame) break;
              if (other_gt != gt && ++others[other_gt] >= options.cover_min_frames) other = true;
            }
            r.outcome =
                other ? ReturnMetrics::Outcome::kOtherPersonId : ReturnMetrics::Outcome::kNewId;
          }
          ++ret.returns;
          switch (r.outcome) {
            case ReturnMetrics::Outcome::kKept:
              ++ret.kept;
              break;
            case ReturnMetrics::Outcome::kNewId:
              ++ret.new_id;
              break;
            case ReturnMetrics::Outcome::kOtherPersonId:
              ++ret.other_person_id;
              break;
            case ReturnMetrics::Outcome::kUntracked:
              ++ret.untracked;
              break;
          }
          ret.list.push_back(r);
        }
        previous_id = id;
        visit_begin = k;
      }
    }
  }
  result.hota =
      EvaluateHota(ground_truth, predictions, options.distance, gate, options.frame_ranges);

  result.protocol = Protocol(options, clear.num_frames);
  result.valid = true;
  return result;
}

}  // namespace mvtrack::eval
