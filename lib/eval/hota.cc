#include "eval/hota.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <map>
#include <optional>
#include <utility>

#include "core/check.h"
#include "core/linear_assignment.h"

namespace mvtrack::eval {
namespace {

constexpr int kNumAlphas = 19;
// TrackEval compares with np.finfo('float').eps margins; the same here.
constexpr double kEps = std::numeric_limits<double>::epsilon();

using IdPair = std::pair<std::int64_t, std::int64_t>;  // (gt id, prediction id)

// Similarity of every (gt, prediction) pair of one frame, row-major n_gt x n_pred.
Eigen::MatrixXd Similarity(const AlignedFrame& f, DistanceKind distance, double threshold_m) {
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(f.gt.size()),
                                            static_cast<Eigen::Index>(f.pred.size()));
  for (std::size_t i = 0; i < f.gt.size(); ++i) {
    for (std::size_t j = 0; j < f.pred.size(); ++j) {
      const std::optional<double> d = ObjectDistance(distance, *f.gt[i], *f.pred[j]);
      if (d) {
        s(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
            std::max(0.0, 1.0 - *d / threshold_m);
      }
    }
  }
  return s;
}

double Mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x;
  return v.empty() ? std::numeric_limits<double>::quiet_NaN() : sum / static_cast<double>(v.size());
}

}  // namespace

HotaMetrics EvaluateHota(const EvalSequence& ground_truth,
                         const EvalSequence& predictions,
                         DistanceKind distance,
                         double threshold_m,
                         const std::vector<FrameRange>& ranges) {
  MVTRACK_CHECK_MSG(std::isfinite(threshold_m) && threshold_m > 0.0,
                    "EvaluateHota: threshold_m must be finite and > 0");
  HotaMetrics h;
  for (int a = 0; a < kNumAlphas; ++a) h.alphas.push_back(0.05 * (a + 1));
  const auto n_alpha = static_cast<std::size_t>(kNumAlphas);
  h.tp.assign(n_alpha, 0);
  h.fn.assign(n_alpha, 0);
  h.fp.assign(n_alpha, 0);
  std::vector<double> loc_sum(n_alpha, 0.0);

  const std::vector<AlignedFrame> frames = AlignFrames(ground_truth, predictions, ranges);
  std::int64_t num_gt = 0;
  std::int64_t num_pred = 0;
  for (const AlignedFrame& f : frames) {
    num_gt += static_cast<std::int64_t>(f.gt.size());
    num_pred += static_cast<std::int64_t>(f.pred.size());
  }

  const auto finish = [&]() {
    for (std::size_t a = 0; a < n_alpha; ++a) {
      const auto tp = static_cast<double>(h.tp[a]);
      const auto fn = static_cast<double>(h.fn[a]);
      const auto fp = static_cast<double>(h.fp[a]);
      h.det_re.push_back(tp / std::max(1.0, tp + fn));
      h.det_pr.push_back(tp / std::max(1.0, tp + fp));
      h.det_a.push_back(tp / std::max(1.0, tp + fn + fp));
      h.loc_a.push_back(std::max(1e-10, loc_sum[a]) / std::max(1e-10, tp));
      h.hota.push_back(std::sqrt(h.det_a[a] * h.ass_a[a]));
    }
    h.mean_hota = Mean(h.hota);
    h.mean_det_a = Mean(h.det_a);
    h.mean_ass_a = Mean(h.ass_a);
    h.mean_loc_a = Mean(h.loc_a);
    return h;
  };

  if (num_pred == 0 || num_gt == 0) {
    for (std::size_t a = 0; a < n_alpha; ++a) {
      h.fn[a] = num_gt;
      h.fp[a] = num_pred;
    }
    h.ass_a.assign(n_alpha, 0.0);
    h.ass_re.assign(n_alpha, 0.0);
    h.ass_pr.assign(n_alpha, 0.0);
    return finish();
  }

  // Pass 1: per id, the frames it appears in; per id pair, the potential matches (the
  // similarity normalised like a Jaccard index within the frame).
  std::map<std::int64_t, double> gt_count;
  std::map<std::int64_t, double> pred_count;
  std::map<IdPair, double> potential;
  for (const AlignedFrame& f : frames) {
    for (const EvalObject* g : f.gt) gt_count[g->id] += 1.0;
    for (const EvalObject* p : f.pred) pred_count[p->id] += 1.0;
    if (f.gt.empty() || f.pred.empty()) continue;
    const Eigen::MatrixXd s = Similarity(f, distance, threshold_m);
    const Eigen::VectorXd row_sum = s.rowwise().sum();
    const Eigen::RowVectorXd col_sum = s.colwise().sum();
    for (Eigen::Index i = 0; i < s.rows(); ++i) {
      for (Eigen::Index j = 0; j < s.cols(); ++j) {
        const double denom = col_sum(j) + row_sum(i) - s(i, j);
        if (!(denom > kEps) || s(i, j) == 0.0) continue;
        potential[{f.gt[static_cast<std::size_t>(i)]->id,
                   f.pred[static_cast<std::size_t>(j)]->id}] += s(i, j) / denom;
      }
    }
  }
  const auto alignment = [&](std::int64_t g, std::int64_t p) {
    const auto it = potential.find({g, p});
    if (it == potential.end()) return 0.0;
    return it->second / (gt_count[g] + pred_count[p] - it->second);
  };

  // Pass 2: per frame the assignment maximising alignment * similarity; per alpha the pairs
  // whose similarity reaches alpha are true positives.
  std::vector<std::map<IdPair, double>> matches(n_alpha);
  for (const AlignedFrame& f : frames) {
    const auto n_g = static_cast<std::int64_t>(f.gt.size());
    const auto n_p = static_cast<std::int64_t>(f.pred.size());
    if (f.gt.empty() || f.pred.empty()) {
      for (std::size_t a = 0; a < n_alpha; ++a) {
        h.fn[a] += n_g;
        h.fp[a] += n_p;
      }
      continue;
    }
    const Eigen::MatrixXd s = Similarity(f, distance, threshold_m);
    Eigen::MatrixXd cost(s.rows(), s.cols());
    for (Eigen::Index i = 0; i < s.rows(); ++i) {
      for (Eigen::Index j = 0; j < s.cols(); ++j) {
        cost(i, j) = -alignment(f.gt[static_cast<std::size_t>(i)]->id,
                                f.pred[static_cast<std::size_t>(j)]->id) *
                     s(i, j);
      }
    }
    // Every pair allowed: a complete assignment of min(n_g, n_p) pairs with the least cost,
    // i.e. the largest score (scipy's linear_sum_assignment on -score in TrackEval).
    const core::Assignment assignment =
        core::SolveAssignment(cost, std::numeric_limits<double>::max());
    for (std::size_t a = 0; a < n_alpha; ++a) {
      std::int64_t tp = 0;
      for (const auto& [i, j] : assignment.matches) {
        const double sim = s(i, j);
        if (!(sim >= h.alphas[a] - kEps)) continue;
        ++tp;
        loc_sum[a] += sim;
        matches[a][{f.gt[static_cast<std::size_t>(i)]->id,
                    f.pred[static_cast<std::size_t>(j)]->id}] += 1.0;
      }
      h.tp[a] += tp;
      h.fn[a] += n_g - tp;
      h.fp[a] += n_p - tp;
    }
  }

  // Association: per matched id pair, the Jaccard index of the two ids' trajectories, averaged
  // over the true positives.
  for (std::size_t a = 0; a < n_alpha; ++a) {
    double ass_a = 0.0;
    double ass_re = 0.0;
    double ass_pr = 0.0;
    for (const auto& [ids, count] : matches[a]) {
      const double g = gt_count[ids.first];
      const double p = pred_count[ids.second];
      ass_a += count * count / std::max(1.0, g + p - count);
      ass_re += count * count / std::max(1.0, g);
      ass_pr += count * count / std::max(1.0, p);
    }
    const double tp = std::max(1.0, static_cast<double>(h.tp[a]));
    h.ass_a.push_back(ass_a / tp);
    h.ass_re.push_back(ass_re / tp);
    h.ass_pr.push_back(ass_pr / tp);
  }
  return finish();
}

}  // namespace mvtrack::eval
