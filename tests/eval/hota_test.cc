#include "eval/hota.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "eval/eval_test_util.h"
#include "eval/tracking_metrics.h"

namespace mvtrack::eval {
namespace {

using testing::At;

double Mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

TEST_CASE("HOTA: perfect tracking scores 1 everywhere", "[unit]") {
  EvalSequence gt, pred;
  for (FrameIndex f = 0; f < 4; ++f) {
    gt.push_back({f, {At(1, static_cast<double>(f) * 0.1, 0.0)}});
    pred.push_back({f, {At(7, static_cast<double>(f) * 0.1, 0.0)}});
  }
  const HotaMetrics h = EvaluateHota(gt, pred, DistanceKind::kFootprint, 0.5, {});
  REQUIRE(h.alphas.size() == 19);
  CHECK(h.alphas.front() == Approx(0.05));
  CHECK(h.alphas.back() == Approx(0.95));
  CHECK(h.mean_hota == Approx(1.0));
  CHECK(h.mean_det_a == Approx(1.0));
  CHECK(h.mean_ass_a == Approx(1.0));
  CHECK(h.mean_loc_a == Approx(1.0));
  CHECK(h.tp.front() == 4);
  CHECK(h.fn.front() == 0);
  CHECK(h.fp.front() == 0);
}

TEST_CASE("HOTA: one person split into two ids halves the association", "[unit]") {
  // GT 1 in frames 0-3; prediction 5 in frames 0-1 and 6 in frames 2-3, exactly on it.
  // DetA = 1; each id pair matched twice, |gt| = 4, |pred| = 2: Jaccard 2 / (4 + 2 - 2) = 0.5,
  // AssA = (2 * 0.5 + 2 * 0.5) / 4 = 0.5, HOTA = sqrt(0.5); AssRe = 0.5, AssPr = 1.
  EvalSequence gt, pred;
  for (FrameIndex f = 0; f < 4; ++f) {
    gt.push_back({f, {At(1, 0.0, 0.0)}});
    pred.push_back({f, {At(f < 2 ? 5 : 6, 0.0, 0.0)}});
  }
  const HotaMetrics h = EvaluateHota(gt, pred, DistanceKind::kFootprint, 0.5, {});
  CHECK(h.mean_det_a == Approx(1.0));
  CHECK(h.mean_ass_a == Approx(0.5));
  CHECK(h.mean_hota == Approx(std::sqrt(0.5)));
  CHECK(Mean(h.ass_re) == Approx(0.5));
  CHECK(Mean(h.ass_pr) == Approx(1.0));
}

TEST_CASE("HOTA: localisation error removes the strict thresholds", "[unit]") {
  // 0.11 m off with a 0.5 m gate: similarity 0.78, a true positive for alpha 0.05 ... 0.75
  // (15 of 19 thresholds), nothing for 0.80 ... 0.95. HOTA(alpha) = 1 or 0: mean 15/19;
  // LocA = 0.78 where there are true positives, 1 (TrackEval's convention) where none.
  EvalSequence gt, pred;
  for (FrameIndex f = 0; f < 3; ++f) {
    gt.push_back({f, {At(1, 0.0, 0.0)}});
    pred.push_back({f, {At(2, 0.11, 0.0)}});
  }
  const HotaMetrics h = EvaluateHota(gt, pred, DistanceKind::kFootprint, 0.5, {});
  CHECK(h.mean_hota == Approx(15.0 / 19.0));
  CHECK(h.mean_det_a == Approx(15.0 / 19.0));
  CHECK(h.mean_ass_a == Approx(15.0 / 19.0));
  CHECK(h.mean_loc_a == Approx((15.0 * 0.78 + 4.0) / 19.0));
  CHECK(h.tp[14] == 3);  // alpha 0.75
  CHECK(h.tp[15] == 0);  // alpha 0.80
  CHECK(h.fn[15] == 3);
  CHECK(h.fp[15] == 3);
}

TEST_CASE("HOTA: a false positive halves detection accuracy", "[unit]") {
  // GT 1 at the origin; prediction 3 on it and prediction 4 far away, two frames: TP 2, FP 2,
  // DetA = 2 / 4 = 0.5; the matched pair is one id pair throughout: AssA = 1.
  EvalSequence gt, pred;
  for (FrameIndex f = 0; f < 2; ++f) {
    gt.push_back({f, {At(1, 0.0, 0.0)}});
    pred.push_back({f, {At(3, 0.0, 0.0), At(4, 5.0, 5.0)}});
  }
  const HotaMetrics h = EvaluateHota(gt, pred, DistanceKind::kFootprint, 0.5, {});
  CHECK(h.mean_det_a == Approx(0.5));
  CHECK(h.mean_ass_a == Approx(1.0));
  CHECK(h.mean_hota == Approx(std::sqrt(0.5)));
}

TEST_CASE("HOTA: the global alignment picks the id that follows the person", "[unit]") {
  // Two predictions near GT 1 in every frame: 8 is on it in all 4 frames, 9 only in frame 0,
  // and in frame 0 9 is slightly closer. Frame-wise nearest matching would take 9 in frame 0;
  // HOTA's score (global alignment x similarity) takes 8 everywhere: AssA = 1 for the matched
  // pair, 9 is a false positive in frame 0.
  EvalSequence gt, pred;
  gt.push_back({0, {At(1, 0.0, 0.0)}});
  pred.push_back({0, {At(8, 0.02, 0.0), At(9, 0.01, 0.0)}});
  for (FrameIndex f = 1; f < 4; ++f) {
    gt.push_back({f, {At(1, 0.0, 0.0)}});
    pred.push_back({f, {At(8, 0.02, 0.0)}});
  }
  const HotaMetrics h = EvaluateHota(gt, pred, DistanceKind::kFootprint, 0.5, {});
  CHECK(h.tp.front() == 4);
  CHECK(h.fp.front() == 1);
  CHECK(h.mean_ass_a == Approx(1.0));
  CHECK(h.mean_det_a == Approx(4.0 / 5.0));
}

TEST_CASE("HOTA: empty sides", "[unit]") {
  EvalSequence gt = {{0, {At(1, 0.0, 0.0)}}, {1, {At(1, 0.0, 0.0)}}};
  const HotaMetrics none = EvaluateHota(gt, {}, DistanceKind::kFootprint, 0.5, {});
  CHECK(none.mean_hota == 0.0);
  CHECK(none.fn.front() == 2);
  CHECK(none.mean_loc_a == Approx(1.0));
  const HotaMetrics no_gt = EvaluateHota({}, gt, DistanceKind::kFootprint, 0.5, {});
  CHECK(no_gt.mean_hota == 0.0);
  CHECK(no_gt.fp.front() == 2);
}

TEST_CASE("Identity coverage: id transfers and fragmentations", "[unit]") {
  // Prediction 1 follows GT 10 in frames 0-19 and GT 20 in frames 20-39 (a transfer); GT 20
  // is followed by prediction 2 in frames 0-19 (so GT 20 is also fragmented).
  EvalSequence gt, pred;
  for (FrameIndex f = 0; f < 40; ++f) {
    if (f < 20) {
      gt.push_back({f, {At(10, 0.0, 0.0), At(20, 3.0, 0.0)}});
      pred.push_back({f, {At(1, 0.0, 0.0), At(2, 3.0, 0.0)}});
    } else {
      gt.push_back({f, {At(20, 3.0, 0.0)}});
      pred.push_back({f, {At(1, 3.0, 0.0)}});
    }
  }
  TrackingOptions o;
  o.cover_min_frames = 15;
  const TrackingEvaluation e = EvaluateTracking(gt, pred, o);
  REQUIRE(e.valid);
  REQUIRE(e.coverage.transfers.size() == 1);
  CHECK(e.coverage.transfers[0].prediction_id == 1);
  CHECK(e.coverage.transfers[0].gt_ids == std::vector<std::int64_t>{10, 20});
  REQUIRE(e.coverage.fragmentations.size() == 1);
  CHECK(e.coverage.fragmentations[0].gt_id == 20);
  CHECK(e.coverage.fragmentations[0].prediction_ids == std::vector<std::int64_t>{2, 1});
  CHECK(e.coverage.cover_min_frames == 15);
  // A cover needs 21 frames now: nothing counts twice.
  o.cover_min_frames = 21;
  const TrackingEvaluation strict = EvaluateTracking(gt, pred, o);
  CHECK(strict.coverage.transfers.empty());
  CHECK(strict.coverage.fragmentations.empty());
  // The same sequence's HOTA is the one EvaluateHota computes.
  CHECK(e.hota.mean_hota ==
        Approx(EvaluateHota(gt, pred, DistanceKind::kFootprint, 0.5, {}).mean_hota));
  o.cover_min_frames = 0;
  std::string why;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("cover_min_frames") != std::string::npos);
}

}  // namespace
}  // namespace mvtrack::eval
