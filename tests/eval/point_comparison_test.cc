// ComparePoints on hand-made frames; every expected value is derived in the comments.

#include "eval/point_comparison.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "eval_test_util.h"

namespace mvtrack::eval {
namespace {

using testing::Add;
using testing::At;

TEST_CASE("Point comparison: counts, one-to-one pairs, gate and distance statistics", "[unit]") {
  // Frame 0: reference points at (0, 0) and (2, 0); footprints at (0.1, 0), (2, 0.3) and a
  //          spurious one at (5, 5) -> pairs 0.1 and 0.3, the third is unmatched.
  // Frame 1: reference (0, 0), (1, 0); footprint (0.5, 0) is 0.5 m from both: one-to-one, so
  //          only one pair (0.5, on the gate: counted); the footprint's ids are irrelevant.
  // Frame 2: reference (0, 0); no footprint line at all -> 1 reference, 0 predicted.
  // Frame 3: footprint (3, 4) and reference (0, 0): 5 m apart, beyond the gate -> no pair.
  EvalSequence ref;
  EvalSequence pred;
  Add(&ref, 0, At(0, 0.0, 0.0));
  Add(&ref, 0, At(1, 2.0, 0.0));
  Add(&pred, 0, At(7, 0.1, 0.0, 1.5));  // height is ignored
  Add(&pred, 0, At(8, 2.0, 0.3));
  Add(&pred, 0, At(9, 5.0, 5.0));
  Add(&ref, 1, At(0, 0.0, 0.0));
  Add(&ref, 1, At(1, 1.0, 0.0));
  Add(&pred, 1, At(7, 0.5, 0.0));
  Add(&ref, 2, At(0, 0.0, 0.0));
  Add(&ref, 3, At(0, 0.0, 0.0));
  Add(&pred, 3, At(3, 3.0, 4.0));

  const PointComparison r = ComparePoints(ref, pred, PointComparisonOptions{});
  REQUIRE(r.valid);
  REQUIRE(r.frames.size() == 4);
  CHECK(r.frames[0].num_reference == 2);
  CHECK(r.frames[0].num_predicted == 3);
  CHECK(r.frames[0].num_matched == 2);
  CHECK(r.frames[1].num_matched == 1);
  CHECK(r.frames[2].num_reference == 1);
  CHECK(r.frames[2].num_predicted == 0);
  CHECK(r.frames[3].num_matched == 0);
  // Totals: reference 2 + 2 + 1 + 1 = 6, predicted 3 + 1 + 0 + 1 = 5, matched 2 + 1 = 3.
  CHECK(r.num_reference == 6);
  CHECK(r.num_predicted == 5);
  CHECK(r.num_matched == 3);
  CHECK(r.precision == Approx(3.0 / 5.0));
  CHECK(r.recall == Approx(3.0 / 6.0));
  // Count differences (pred - ref): +1, -1, -1, 0 -> mean 0 - 1/4 = -0.25, mean |.| = 3/4.
  CHECK(r.frames_with_equal_count == 1);
  CHECK(r.mean_count_difference == Approx(-0.25));
  CHECK(r.mean_abs_count_difference == Approx(0.75));
  CHECK(r.max_abs_count_difference == 1);
  // Distances {0.1, 0.3, 0.5}: median 0.3, mean 0.3, p90 = ceil(2.7) = 3rd = 0.5, max 0.5.
  CHECK(r.median_distance_m == Approx(0.3));
  CHECK(r.mean_distance_m == Approx(0.3));
  CHECK(r.p90_distance_m == Approx(0.5));
  CHECK(r.max_distance_m == Approx(0.5));
  CHECK(r.protocol.find("0.500 m") != std::string::npos);
}

TEST_CASE("Point comparison: the most pairs first, not nearest-first", "[unit]") {
  // Reference a = (0, 0), b = (0.4, 0); footprints p = (0.3, 0), q = (0.75, 0).
  // Nearest-first would pair p-b (0.1) and leave q-a (0.75, beyond the 0.5 m gate): one pair.
  // Maximising the number of pairs first gives p-a (0.3) and q-b (0.35).
  EvalSequence ref;
  EvalSequence pred;
  Add(&ref, 0, At(0, 0.0, 0.0));
  Add(&ref, 0, At(1, 0.4, 0.0));
  Add(&pred, 0, At(0, 0.3, 0.0));
  Add(&pred, 0, At(1, 0.75, 0.0));
  const PointComparison r = ComparePoints(ref, pred, PointComparisonOptions{});
  REQUIRE(r.valid);
  CHECK(r.num_matched == 2);
  // Distances {0.3, 0.35}: even count -> median = mean of the two = 0.325.
  CHECK(r.median_distance_m == Approx(0.325));
  CHECK(r.max_distance_m == Approx(0.35));
}

TEST_CASE("Point comparison: frame ranges, empty input, bad options", "[unit]") {
  EvalSequence ref;
  EvalSequence pred;
  for (FrameIndex f = 0; f < 5; ++f) {
    Add(&ref, f, At(0, 0.0, 0.0));
    Add(&pred, f, At(0, 0.2 * static_cast<double>(f), 0.0));
  }
  PointComparisonOptions options;
  options.frame_ranges = {{1, 2}};
  const PointComparison r = ComparePoints(ref, pred, options);
  REQUIRE(r.valid);
  // Frames 1, 2: distances 0.2 and 0.4 -> median 0.3.
  CHECK(r.frames.size() == 2);
  CHECK(r.median_distance_m == Approx(0.3));

  const PointComparison empty = ComparePoints({}, {}, PointComparisonOptions{});
  REQUIRE(empty.valid);
  CHECK(empty.frames.empty());
  CHECK(std::isnan(empty.median_distance_m));
  CHECK(std::isnan(empty.mean_abs_count_difference));
  CHECK(std::isnan(empty.precision));

  PointComparisonOptions bad;
  bad.gate_m = 0.0;
  const PointComparison b = ComparePoints(ref, pred, bad);
  CHECK_FALSE(b.valid);
  CHECK(b.error.find("gate_m") != std::string::npos);

  EvalSequence duplicate_ids;
  Add(&duplicate_ids, 0, At(4, 0.0, 0.0));
  Add(&duplicate_ids, 0, At(4, 1.0, 0.0));
  const PointComparison d = ComparePoints(duplicate_ids, pred, PointComparisonOptions{});
  CHECK_FALSE(d.valid);
  CHECK(d.error.find("reference") != std::string::npos);
}

TEST_CASE("Point comparison: MODA, MODP and the evaluated area", "[unit]") {
  // Frame 0: reference (0, 0), (3, 0), (20, 0); footprints (0.1, 0), (3, 0.4), (8, 8).
  //   Pairs 0.1 and 0.4 m; (8, 8) is a false positive, (20, 0) a miss.
  // Frame 1: reference (0, 0); footprints (0, 0.2) and (-9, 0).
  //   Pair 0.2 m; (-9, 0) a false positive.
  // Everywhere: TP 3, FP 2, FN 1, GT 4 -> MODA = 1 - 3/4 = 0.25; MODP = mean of 1 - d / 0.5 =
  //   (0.8 + 0.2 + 0.6) / 3 = 0.5333; mean matched distance (0.1 + 0.4 + 0.2) / 3 = 0.2333.
  // Area x in [-1, 10], y in [-1, 10]: drops the reference (20, 0) and the footprint (-9, 0):
  //   TP 3, FP 1, FN 0, GT 3 -> MODA = 1 - 1/3; precision 3/4, recall 1.
  EvalSequence ref;
  EvalSequence pred;
  Add(&ref, 0, At(0, 0.0, 0.0));
  Add(&ref, 0, At(1, 3.0, 0.0));
  Add(&ref, 0, At(2, 20.0, 0.0));
  Add(&pred, 0, At(5, 0.1, 0.0));
  Add(&pred, 0, At(6, 3.0, 0.4));
  Add(&pred, 0, At(7, 8.0, 8.0));
  Add(&ref, 1, At(0, 0.0, 0.0));
  Add(&pred, 1, At(5, 0.0, 0.2));
  Add(&pred, 1, At(6, -9.0, 0.0));

  const PointComparison all = ComparePoints(ref, pred, PointComparisonOptions{});
  REQUIRE(all.valid);
  CHECK(all.num_matched == 3);
  CHECK(all.false_positives == 2);
  CHECK(all.misses == 1);
  CHECK(all.moda == Approx(0.25));
  CHECK(all.modp == Approx(1.6 / 3.0));
  CHECK(all.mean_distance_m == Approx(0.7 / 3.0));
  CHECK(all.num_reference_outside == 0);
  CHECK(all.protocol.find("Area: everywhere") != std::string::npos);

  PointComparisonOptions options;
  options.area = PointComparisonOptions::Area{-1.0, 10.0, -1.0, 10.0};
  const PointComparison in = ComparePoints(ref, pred, options);
  REQUIRE(in.valid);
  CHECK(in.num_reference == 3);
  CHECK(in.num_predicted == 4);
  CHECK(in.num_reference_outside == 1);
  CHECK(in.num_predicted_outside == 1);
  CHECK(in.false_positives == 1);
  CHECK(in.misses == 0);
  CHECK(in.moda == Approx(1.0 - 1.0 / 3.0));
  CHECK(in.precision == Approx(0.75));
  CHECK(in.recall == Approx(1.0));
  CHECK(in.protocol.find("x in [-1.00, 10.00] m") != std::string::npos);

  PointComparisonOptions bad;
  bad.area = PointComparisonOptions::Area{1.0, 1.0, 0.0, 2.0};
  const PointComparison b = ComparePoints(ref, pred, bad);
  CHECK_FALSE(b.valid);
  CHECK(b.error.find("area") != std::string::npos);
  // No reference points: MODA undefined.
  const PointComparison none = ComparePoints({}, pred, PointComparisonOptions{});
  REQUIRE(none.valid);
  CHECK(std::isnan(none.moda));
  CHECK(none.false_positives == 5);  // all five footprints
}

}  // namespace
}  // namespace mvtrack::eval
