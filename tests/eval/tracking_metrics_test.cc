// Hand-made cases for CLEAR MOT, IDF1 and MPJPE. Every expected value is derived in the
// comments from the constructed ground truth and predictions.

#include "eval/tracking_metrics.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "eval_test_util.h"

namespace mvtrack::eval {
namespace {

using testing::Add;
using testing::At;

TEST_CASE("Perfect run: MOTA = 1, IDF1 = 1, MOTP = constant offset", "[unit]") {
  // Two people, 4 frames; predictions (other id namespace: 10, 20) sit 0.1 m off in x.
  EvalSequence gt;
  EvalSequence pred;
  for (FrameIndex f = 0; f < 4; ++f) {
    const double x = 0.25 * static_cast<double>(f);
    Add(&gt, f, At(1, x, 0.0));
    Add(&gt, f, At(2, 5.0, x));
    Add(&pred, f, At(10, x + 0.1, 0.0));
    Add(&pred, f, At(20, 5.1, x));
  }
  const TrackingEvaluation r = EvaluateTracking(gt, pred, TrackingOptions{});
  REQUIRE(r.valid);
  // 8 GT object-frames, all matched: FN = FP = IDSW = 0 -> MOTA = 1 - 0/8 = 1.
  CHECK(r.clear.num_frames == 4);
  CHECK(r.clear.num_objects == 8);
  CHECK(r.clear.num_predictions == 8);
  CHECK(r.clear.num_unique_objects == 2);
  CHECK(r.clear.num_unique_predictions == 2);
  CHECK(r.clear.num_matches == 8);
  CHECK(r.clear.num_misses == 0);
  CHECK(r.clear.num_false_positives == 0);
  CHECK(r.clear.num_switches == 0);
  CHECK(r.clear.mota == 1.0);
  // Every matched distance is 0.1 m -> MOTP = 0.1.
  CHECK(r.clear.motp_m == Approx(0.1).margin(1e-12));
  // Each GT within the gate of one track in all 4 frames: IDTP = 8 -> IDF1 = 16/16 = 1.
  CHECK(r.identity.idtp == 8);
  CHECK(r.identity.idfp == 0);
  CHECK(r.identity.idfn == 0);
  CHECK(r.identity.idf1 == 1.0);
  CHECK(r.identity.idp == 1.0);
  CHECK(r.identity.idr == 1.0);
  REQUIRE(r.identity.matches.size() == 2);
  CHECK(r.identity.matches[0].gt_id == 1);
  CHECK(r.identity.matches[0].prediction_id == 10);
  CHECK(r.identity.matches[1].gt_id == 2);
  CHECK(r.identity.matches[1].prediction_id == 20);
  CHECK(r.clear.mostly_tracked == 2);
  CHECK(r.clear.mostly_lost == 0);
  CHECK(r.clear.num_fragmentations == 0);
  // No joints at all: MPJPE undefined.
  CHECK(r.pose.num_pairs == 0);
  CHECK(std::isnan(r.pose.mpjpe_m));
  CHECK(r.protocol.find("footprint_xy") != std::string::npos);
  CHECK(r.protocol.find("0.500 m") != std::string::npos);
}

TEST_CASE("One identity switch: IDSW = 1, MOTA and IDF1 by hand", "[unit]") {
  // GT 1 over frames 0..5. Track 7 follows it in frames 0..3, track 8 in frames 4..5.
  EvalSequence gt;
  EvalSequence pred;
  for (FrameIndex f = 0; f < 6; ++f) {
    const double x = 0.2 * static_cast<double>(f);
    Add(&gt, f, At(1, x, 0.0));
    Add(&pred, f, At(f < 4 ? 7 : 8, x, 0.0));
  }
  const TrackingEvaluation r = EvaluateTracking(gt, pred, TrackingOptions{});
  REQUIRE(r.valid);
  // Frame 4: GT 1's last match (7) is absent, step 2 matches it to 8 -> one switch.
  CHECK(r.clear.num_switches == 1);
  REQUIRE(r.switches.size() == 1);
  CHECK(r.switches[0].frame == 4);
  CHECK(r.switches[0].gt_id == 1);
  CHECK(r.switches[0].previous_prediction_id == 7);
  CHECK(r.switches[0].prediction_id == 8);
  CHECK(r.clear.num_misses == 0);
  CHECK(r.clear.num_false_positives == 0);
  // MOTA = 1 - (0 + 0 + 1) / 6 = 5/6.
  CHECK(r.clear.mota == Approx(5.0 / 6.0));
  // IDF1: GT 1 (6 frames) <-> track 7 (4 frames within the gate) is the best pair:
  // IDTP = 4, IDFN = 6 - 4 = 2, IDFP = 6 - 4 = 2 (track 8's frames).
  // IDF1 = 2*4 / (6 + 6) = 2/3, IDP = 4/6, IDR = 4/6.
  CHECK(r.identity.idtp == 4);
  CHECK(r.identity.idfn == 2);
  CHECK(r.identity.idfp == 2);
  CHECK(r.identity.idf1 == Approx(2.0 / 3.0));
  CHECK(r.identity.idp == Approx(4.0 / 6.0));
  CHECK(r.identity.idr == Approx(4.0 / 6.0));
  REQUIRE(r.identity.matches.size() == 1);
  CHECK(r.identity.matches[0].prediction_id == 7);
  CHECK(r.identity.matches[0].frames_within_gate == 4);
}

TEST_CASE("A false positive lowers MOTA and IDP but not IDR", "[unit]") {
  // GT 1 in frames 0..2 followed exactly by track 1; in frame 1 a spurious track 2 lies 10 m
  // away (outside the 0.5 m gate).
  EvalSequence gt;
  EvalSequence pred;
  for (FrameIndex f = 0; f < 3; ++f) {
    Add(&gt, f, At(1, 1.0, 1.0));
    Add(&pred, f, At(1, 1.0, 1.0));
  }
  Add(&pred, 1, At(2, 11.0, 1.0));
  const TrackingEvaluation r = EvaluateTracking(gt, pred, TrackingOptions{});
  REQUIRE(r.valid);
  CHECK(r.clear.num_false_positives == 1);
  CHECK(r.clear.num_misses == 0);
  CHECK(r.clear.num_switches == 0);
  CHECK(r.clear.num_predictions == 4);
  // MOTA = 1 - 1/3 = 2/3.
  CHECK(r.clear.mota == Approx(2.0 / 3.0));
  // IDTP = 3 (GT 1 <-> track 1), IDFP = 4 - 3 = 1, IDFN = 0:
  // IDF1 = 6 / (3 + 4) = 6/7, IDP = 3/4, IDR = 1.
  CHECK(r.identity.idtp == 3);
  CHECK(r.identity.idf1 == Approx(6.0 / 7.0));
  CHECK(r.identity.idp == Approx(0.75));
  CHECK(r.identity.idr == 1.0);
  CHECK(r.clear.num_unique_predictions == 2);
}

TEST_CASE("A missed frame is a false negative and a fragmentation", "[unit]") {
  // GT 1 in frames 0..3; track 1 is missing in frame 2.
  EvalSequence gt;
  EvalSequence pred;
  for (FrameIndex f = 0; f < 4; ++f) {
    Add(&gt, f, At(1, 2.0, 3.0));
    if (f != 2) Add(&pred, f, At(1, 2.0, 3.0));
  }
  SECTION("no prediction at all in that frame") {
    const TrackingEvaluation r = EvaluateTracking(gt, pred, TrackingOptions{});
    REQUIRE(r.valid);
    // FN = 1 -> MOTA = 1 - 1/4 = 0.75. Matched T T F T -> one fragmentation.
    CHECK(r.clear.num_misses == 1);
    CHECK(r.clear.num_false_positives == 0);
    CHECK(r.clear.mota == Approx(0.75));
    CHECK(r.clear.num_fragmentations == 1);
    // IDTP = 3: IDF1 = 6 / (4 + 3) = 6/7, IDP = 1, IDR = 3/4.
    CHECK(r.identity.idf1 == Approx(6.0 / 7.0));
    CHECK(r.identity.idp == 1.0);
    CHECK(r.identity.idr == Approx(0.75));
    // 3/4 matched < 80%: partially tracked.
    REQUIRE(r.objects.size() == 1);
    CHECK(r.objects[0].frames_present == 4);
    CHECK(r.objects[0].frames_matched == 3);
    CHECK(r.objects[0].coverage == TrackCoverage::kPartiallyTracked);
  }
  SECTION("a prediction just outside the gate is a miss and a false positive") {
    Add(&pred, 2, At(1, 2.0 + 0.5001, 3.0));
    const TrackingEvaluation r = EvaluateTracking(gt, pred, TrackingOptions{});
    REQUIRE(r.valid);
    // FN = 1, FP = 1 -> MOTA = 1 - 2/4 = 0.5.
    CHECK(r.clear.num_misses == 1);
    CHECK(r.clear.num_false_positives == 1);
    CHECK(r.clear.mota == Approx(0.5));
  }
  SECTION("a prediction exactly on the gate is matched (d <= gate)") {
    // 0.5 and 2.5 are exact in binary: the distance is exactly 0.5.
    Add(&pred, 2, At(1, 2.5, 3.0));
    const TrackingEvaluation r = EvaluateTracking(gt, pred, TrackingOptions{});
    REQUIRE(r.valid);
    CHECK(r.clear.num_misses == 0);
    CHECK(r.clear.mota == 1.0);
    // MOTP = (0 + 0 + 0.5 + 0) / 4.
    CHECK(r.clear.motp_m == Approx(0.125));
  }
}

TEST_CASE("Two crossing people with swapped track ids", "[unit]") {
  // GT 1 walks along y = 0 from x = 0 to 4 (x = t), GT 2 along y = dy from x = 4 to 0
  // (x = 4 - t), frames t = 0..4. The tracker swaps at the crossing (t = 2): track 1 follows
  // GT 1 for t < 2 and GT 2 from t = 2, track 2 the other way round.
  const auto make = [](double dy, EvalSequence* gt, EvalSequence* pred) {
    for (FrameIndex f = 0; f <= 4; ++f) {
      const double t = static_cast<double>(f);
      Add(gt, f, At(1, t, 0.0));
      Add(gt, f, At(2, 4.0 - t, dy));
      const bool swapped = f >= 2;
      Add(pred, f, swapped ? At(1, 4.0 - t, dy) : At(1, t, 0.0));
      Add(pred, f, swapped ? At(2, t, 0.0) : At(2, 4.0 - t, dy));
    }
  };
  SECTION("lanes 0.3 m apart: the old pairs survive the crossing frame, switch one frame later") {
    EvalSequence gt;
    EvalSequence pred;
    make(0.3, &gt, &pred);
    const TrackingEvaluation r = EvaluateTracking(gt, pred, TrackingOptions{});
    REQUIRE(r.valid);
    // t = 2: GT 1 (2, 0) keeps track 1 at (2, 0.3): 0.3 m <= gate (step 1), same for GT 2 and
    // track 2. t = 3: both old pairs are 2 m apart, step 2 matches GT 1 <-> 2, GT 2 <-> 1:
    // two switches, at frame 3. FN = FP = 0 -> MOTA = 1 - 2/10 = 0.8.
    CHECK(r.clear.num_switches == 2);
    REQUIRE(r.switches.size() == 2);
    CHECK(r.switches[0].frame == 3);
    CHECK(r.switches[1].frame == 3);
    CHECK(r.clear.num_misses == 0);
    CHECK(r.clear.num_false_positives == 0);
    CHECK(r.clear.mota == Approx(0.8));
    // MOTP = (2 * 0.3) / 10 = 0.06.
    CHECK(r.clear.motp_m == Approx(0.06));
    // c(1,1) = t 0,1,2 = 3; c(1,2) = t 2,3,4 = 3; c(2,1) = 3; c(2,2) = 3. IDTP = 6:
    // IDF1 = 12 / 20 = 0.6.
    CHECK(r.identity.idtp == 6);
    CHECK(r.identity.idf1 == Approx(0.6));
  }
  SECTION("lanes 0.6 m apart: the switch happens in the crossing frame") {
    EvalSequence gt;
    EvalSequence pred;
    make(0.6, &gt, &pred);
    const TrackingEvaluation r = EvaluateTracking(gt, pred, TrackingOptions{});
    REQUIRE(r.valid);
    // t = 2: old pairs are 0.6 m > gate apart; the exact pairs GT 1 <-> 2, GT 2 <-> 1 win.
    CHECK(r.clear.num_switches == 2);
    REQUIRE(r.switches.size() == 2);
    CHECK(r.switches[0].frame == 2);
    CHECK(r.clear.mota == Approx(0.8));
    CHECK(r.clear.motp_m == 0.0);
    // c(1,1) = 2 (t 0,1), c(1,2) = 3 (t 2,3,4), c(2,1) = 3, c(2,2) = 2: IDTP = 6, IDF1 = 0.6.
    CHECK(r.identity.idtp == 6);
    CHECK(r.identity.idf1 == Approx(0.6));
  }
}

TEST_CASE("A GT keeps its last matched track across a gap even if another is closer", "[unit]") {
  // Frame 0: GT 1 matched to track 5. Frame 1: GT 1 absent. Frame 2: track 5 at 0.4 m, track 6
  // at 0.1 m. py-motmetrics re-establishes the last correspondence first (step 1), so GT 1
  // stays with 5 (no switch) and 6 is a false positive; a plain per-frame assignment would have
  // picked 6 and counted a switch.
  EvalSequence gt = testing::Sequence({{0, {At(1, 0.0, 0.0)}}, {2, {At(1, 0.0, 0.0)}}});
  EvalSequence pred =
      testing::Sequence({{0, {At(5, 0.0, 0.0)}}, {1, {}}, {2, {At(5, 0.4, 0.0), At(6, 0.1, 0.0)}}});
  const TrackingEvaluation r = EvaluateTracking(gt, pred, TrackingOptions{});
  REQUIRE(r.valid);
  CHECK(r.clear.num_frames == 3);
  CHECK(r.clear.num_switches == 0);
  CHECK(r.clear.num_false_positives == 1);
  CHECK(r.clear.motp_m == Approx(0.2));  // (0 + 0.4) / 2
}

TEST_CASE("MT / PT / ML classification at the 80% and 20% boundaries", "[unit]") {
  // Frames 0..9. GT k stands at (10k, 0); its track (id 100 + k) is present exactly in the
  // frames listed, always on the GT.
  struct Spec {
    std::int64_t id;
    std::vector<FrameIndex> present;
    std::vector<FrameIndex> tracked;
  };
  const std::vector<Spec> specs = {
      {1, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9}, {0, 1, 2, 3, 4, 5, 6, 7}},  // 8/10 = 80% -> MT
      {2, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9}, {0, 1, 2, 5, 6, 7, 8}},     // 7/10 -> PT, 1 frag.
      {3, {0, 1, 2, 3, 4}, {2}},                                      // 1/5 = 20% -> PT
      {4, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9}, {9}},                       // 1/10 -> ML
      {5, {0, 1, 2}, {}},                                             // 0/3 -> ML
  };
  EvalSequence gt;
  EvalSequence pred;
  for (const Spec& s : specs) {
    const double x = 10.0 * static_cast<double>(s.id);
    for (const FrameIndex f : s.present) Add(&gt, f, At(s.id, x, 0.0));
    for (const FrameIndex f : s.tracked) Add(&pred, f, At(100 + s.id, x, 0.0));
  }
  const TrackingEvaluation r = EvaluateTracking(gt, pred, TrackingOptions{});
  REQUIRE(r.valid);
  REQUIRE(r.objects.size() == 5);
  CHECK(r.objects[0].coverage == TrackCoverage::kMostlyTracked);
  CHECK(r.objects[1].coverage == TrackCoverage::kPartiallyTracked);
  CHECK(r.objects[2].coverage == TrackCoverage::kPartiallyTracked);
  CHECK(r.objects[3].coverage == TrackCoverage::kMostlyLost);
  CHECK(r.objects[4].coverage == TrackCoverage::kMostlyLost);
  CHECK(r.objects[2].frames_present == 5);
  CHECK(r.objects[2].frames_matched == 1);
  CHECK(r.clear.mostly_tracked == 1);
  CHECK(r.clear.partially_tracked == 2);
  CHECK(r.clear.mostly_lost == 2);
  // Only GT 2 has a miss run between its first and last matched frame (frames 3-4).
  CHECK(r.clear.num_fragmentations == 1);
  // GT object-frames 10+10+5+10+3 = 38, matched 8+7+1+1+0 = 17: FN = 21, MOTA = 1 - 21/38.
  CHECK(r.clear.num_objects == 38);
  CHECK(r.clear.num_misses == 21);
  CHECK(r.clear.mota == Approx(1.0 - 21.0 / 38.0));
}

TEST_CASE("Footprint distance ignores height", "[unit]") {
  const EvalSequence gt = testing::Sequence({{0, {At(1, 1.0, 2.0, 0.0)}}});
  const EvalSequence pred = testing::Sequence({{0, {At(1, 1.0, 2.3, 1.7)}}});
  const TrackingEvaluation r = EvaluateTracking(gt, pred, TrackingOptions{});
  REQUIRE(r.valid);
  CHECK(r.clear.num_matches == 1);
  CHECK(r.clear.motp_m == Approx(0.3));
}

// A 3-joint object; `missing` joints are std::nullopt.
EvalObject Posed(std::int64_t id, const std::vector<std::optional<Vec3>>& joints) {
  EvalObject o = At(id, 0.0, 0.0);
  o.joints = joints;
  return o;
}

TEST_CASE("Mean-joint matching and MPJPE over matched pairs", "[unit]") {
  const Vec3 a(0.0, 0.0, 1.0);
  const Vec3 b(0.0, 0.0, 1.5);
  const Vec3 c(0.3, 0.0, 1.0);
  const Vec3 dx(1.0, 0.0, 0.0);
  const Vec3 dy(0.0, 1.0, 0.0);
  EvalSequence gt;
  EvalSequence pred;
  // Frame 0: errors 0.03 (joint 0), joint 1 missing in the prediction, 0.04 (joint 2).
  Add(&gt, 0, Posed(1, {a, b, c}));
  Add(&pred, 0, Posed(4, {a + 0.03 * dx, std::nullopt, c + 0.04 * dy}));
  // Frame 1: GT joint 2 missing; errors 0.06 (joint 0) and 0.02 (joint 1).
  Add(&gt, 1, Posed(1, {a, b, std::nullopt}));
  Add(&pred, 1, Posed(4, {a + 0.06 * dy, b + 0.02 * dx, c}));
  // Frame 2: the prediction has no joint at all: no common joint, cannot be matched.
  Add(&gt, 2, Posed(1, {a, b, c}));
  Add(&pred, 2, Posed(4, {std::nullopt, std::nullopt, std::nullopt}));
  TrackingOptions options;
  options.distance = DistanceKind::kMeanJoint;
  const TrackingEvaluation r = EvaluateTracking(gt, pred, options);
  REQUIRE(r.valid);
  // Frames 0, 1 matched (mean joint distances 0.035 and 0.04), frame 2 FN + FP.
  CHECK(r.clear.num_matches == 2);
  CHECK(r.clear.num_misses == 1);
  CHECK(r.clear.num_false_positives == 1);
  CHECK(r.clear.motp_m == Approx((0.035 + 0.04) / 2.0));
  // MPJPE = (0.03 + 0.04 + 0.06 + 0.02) / 4 = 0.0375 over 2 pairs and 4 joints.
  CHECK(r.pose.num_pairs == 2);
  CHECK(r.pose.num_joints == 4);
  CHECK(r.pose.mpjpe_m == Approx(0.0375));
  REQUIRE(r.pose.per_joint_mpjpe_m.size() == 3);
  CHECK(r.pose.per_joint_mpjpe_m[0] == Approx(0.045));
  CHECK(r.pose.per_joint_mpjpe_m[1] == Approx(0.02));
  CHECK(r.pose.per_joint_mpjpe_m[2] == Approx(0.04));
  CHECK(r.pose.per_joint_count == std::vector<std::int64_t>{2, 1, 1});
  CHECK(r.protocol.find("mean_joint") != std::string::npos);
}

TEST_CASE("Frame ranges restrict the evaluated frames", "[unit]") {
  // GT 1 in frames 0..9; the track exists only in frames 5..9.
  EvalSequence gt;
  EvalSequence pred;
  for (FrameIndex f = 0; f < 10; ++f) {
    Add(&gt, f, At(1, 0.0, 0.0));
    if (f >= 5) Add(&pred, f, At(1, 0.0, 0.0));
  }
  TrackingOptions options;
  options.frame_ranges = {{5, 7}, {9, 20}};
  const TrackingEvaluation r = EvaluateTracking(gt, pred, options);
  REQUIRE(r.valid);
  CHECK(r.clear.num_frames == 4);  // 5, 6, 7, 9
  CHECK(r.clear.num_objects == 4);
  CHECK(r.clear.mota == 1.0);
  CHECK(r.protocol.find("[5, 7] + [9, 20]") != std::string::npos);
  const TrackingEvaluation all = EvaluateTracking(gt, pred, TrackingOptions{});
  CHECK(all.clear.mota == Approx(0.5));
}

TEST_CASE("Empty inputs give undefined ratios, not errors", "[unit]") {
  const TrackingEvaluation r = EvaluateTracking({}, {}, TrackingOptions{});
  REQUIRE(r.valid);
  CHECK(r.clear.num_objects == 0);
  CHECK(std::isnan(r.clear.mota));
  CHECK(std::isnan(r.clear.motp_m));
  CHECK(std::isnan(r.identity.idf1));
  // Predictions only: every one is a false positive; IDF1 = 0 / (0 + 2) = 0.
  const EvalSequence pred = testing::Sequence({{0, {At(1, 0, 0), At(2, 3, 0)}}});
  const TrackingEvaluation fp = EvaluateTracking({}, pred, TrackingOptions{});
  REQUIRE(fp.valid);
  CHECK(fp.clear.num_false_positives == 2);
  CHECK(std::isnan(fp.clear.mota));
  CHECK(fp.identity.idf1 == 0.0);
  CHECK(fp.identity.idp == 0.0);
}

TEST_CASE("Invalid inputs and options are rejected with a reason", "[unit]") {
  const EvalSequence ok = testing::Sequence({{0, {At(1, 0, 0)}}});
  SECTION("duplicate id in a frame") {
    const EvalSequence bad = testing::Sequence({{0, {At(1, 0, 0), At(1, 2, 0)}}});
    const TrackingEvaluation r = EvaluateTracking(bad, ok, TrackingOptions{});
    CHECK_FALSE(r.valid);
    CHECK(r.error.find("ground truth") != std::string::npos);
    CHECK(r.error.find("more than once") != std::string::npos);
  }
  SECTION("duplicate frame index") {
    EvalSequence bad = ok;
    bad.push_back(ok.front());
    const TrackingEvaluation r = EvaluateTracking(ok, bad, TrackingOptions{});
    CHECK_FALSE(r.valid);
    CHECK(r.error.find("predictions") != std::string::npos);
  }
  SECTION("joint counts differ between the sides") {
    EvalSequence posed = ok;
    posed[0].objects[0].joints.assign(3, Vec3::Zero());
    const TrackingEvaluation r = EvaluateTracking(ok, posed, TrackingOptions{});
    CHECK_FALSE(r.valid);
    CHECK(r.error.find("MakeKeypointMapping") != std::string::npos);
  }
  SECTION("non-finite position") {
    EvalSequence bad = ok;
    bad[0].objects[0].position.x() = std::nan("");
    CHECK_FALSE(EvaluateTracking(bad, ok, TrackingOptions{}).valid);
  }
  SECTION("bad options") {
    TrackingOptions options;
    options.footprint_threshold_m = 0.0;
    const TrackingEvaluation r = EvaluateTracking(ok, ok, options);
    CHECK_FALSE(r.valid);
    CHECK(r.error.find("footprint_threshold_m") != std::string::npos);
    options = TrackingOptions{};
    options.frame_ranges = {{5, 4}};
    CHECK_FALSE(EvaluateTracking(ok, ok, options).valid);
  }
}

}  // namespace
}  // namespace mvtrack::eval

namespace mvtrack::eval {
namespace {

TEST_CASE("Returns: kept, new id, another person's id, untracked", "[unit]") {
  // return_min_gap_frames 5. GT 1 visits [0, 10), [20, 30), [40, 50), [60, 70), [80, 90);
  // GT 2 is present in [0, 30) far away. Predictions: visit 1 id 10; visit 2 id 10 (kept);
  // visit 3 id 11, never anyone else's (new id); visit 4 id 20, which covered GT 2 for 30
  // frames before (another person's id); visit 5 unmatched (untracked).
  EvalSequence gt;
  EvalSequence pred;
  const std::int64_t id_of_visit[] = {10, 10, 11, 20, -1};
  for (int v = 0; v < 5; ++v) {
    for (FrameIndex f = 20 * v; f < 20 * v + 10; ++f) {
      Add(&gt, f, At(1, 0.0, 0.0));
      if (id_of_visit[v] >= 0) Add(&pred, f, At(id_of_visit[v], 0.05, 0.0));
    }
  }
  for (FrameIndex f = 0; f < 30; ++f) {
    Add(&gt, f, At(2, 9.0, 9.0));
    Add(&pred, f, At(20, 9.0, 9.0));
  }
  TrackingOptions o;
  o.return_min_gap_frames = 5;
  const TrackingEvaluation r = EvaluateTracking(gt, pred, o);
  REQUIRE(r.valid);
  const ReturnMetrics& ret = r.returns;
  CHECK(ret.min_gap_frames == 5);
  REQUIRE(ret.returns == 4);
  CHECK(ret.kept == 1);
  CHECK(ret.new_id == 1);
  CHECK(ret.other_person_id == 1);
  CHECK(ret.untracked == 1);
  REQUIRE(ret.list.size() == 4);
  CHECK(ret.list[0].gt_id == 1);
  CHECK(ret.list[0].frame == 20);
  CHECK(ret.list[0].gap_frames == 10);
  CHECK(ret.list[0].before_id == 10);
  CHECK(ret.list[0].after_id == 10);
  CHECK(ret.list[0].outcome == ReturnMetrics::Outcome::kKept);
  CHECK(ret.list[1].outcome == ReturnMetrics::Outcome::kNewId);
  CHECK(ret.list[2].after_id == 20);
  CHECK(ret.list[2].outcome == ReturnMetrics::Outcome::kOtherPersonId);
  CHECK(ret.list[3].after_id == -1);
  CHECK(ret.list[3].outcome == ReturnMetrics::Outcome::kUntracked);
  CHECK(std::string(ReturnOutcomeName(ReturnMetrics::Outcome::kOtherPersonId)) ==
        "other person's id");
  // A gap of exactly the threshold is not a return.
  o.return_min_gap_frames = 10;
  CHECK(EvaluateTracking(gt, pred, o).returns.returns == 0);
  o.return_min_gap_frames = 9;
  CHECK(EvaluateTracking(gt, pred, o).returns.returns == 4);
  o.return_min_gap_frames = 0;
  std::string why;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("return_min_gap_frames") != std::string::npos);
}

}  // namespace
}  // namespace mvtrack::eval
