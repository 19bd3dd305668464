// PCP on hand-made skeletons; every expected value is derived in the comments.

#include "eval/pcp.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "core/keypoint_layout.h"
#include "eval_test_util.h"

namespace mvtrack::eval {
namespace {

int J(const char* name) {
  const core::KeypointLayout& l = core::GetKeypointLayout(core::KeypointLayoutId::kShelf14);
  for (int j = 0; j < l.num_joints(); ++j) {
    if (l.joints[static_cast<std::size_t>(j)] == name) return j;
  }
  FAIL("no joint " << name);
  return -1;
}

// A standing person in the shelf14 layout with the feet centred on (x, y).
EvalObject Person(std::int64_t id, double x, double y) {
  EvalObject o = testing::At(id, x, y);
  o.joints.assign(14, std::nullopt);
  const auto set = [&](const char* name, double dx, double dz) {
    o.joints[static_cast<std::size_t>(J(name))] = Vec3(x + dx, y, dz);
  };
  set("r_ankle", -0.1, 0.05);
  set("r_knee", -0.1, 0.5);
  set("r_hip", -0.1, 0.95);
  set("l_hip", 0.1, 0.95);
  set("l_knee", 0.1, 0.5);
  set("l_ankle", 0.1, 0.05);
  set("r_wrist", -0.25, 0.9);
  set("r_elbow", -0.25, 1.15);
  set("r_shoulder", -0.2, 1.45);
  set("l_shoulder", 0.2, 1.45);
  set("l_elbow", 0.25, 1.15);
  set("l_wrist", 0.25, 0.9);
  set("head_bottom", 0.0, 1.55);
  set("head_top", 0.0, 1.8);
  return o;
}

TEST_CASE("Shelf/Campus protocol: the layout's nine bones plus the derived torso", "[unit]") {
  const PcpProtocol p = ShelfCampusPcpProtocol();
  REQUIRE(p.Validate(14, nullptr));
  REQUIRE(p.bones.size() == 10);
  const core::KeypointLayout& l = core::GetKeypointLayout(core::KeypointLayoutId::kShelf14);
  REQUIRE(l.bones.size() == 9);
  for (std::size_t b = 0; b < 9; ++b) {
    INFO("bone " << b);
    REQUIRE(p.bones[b].a.size() == 1);
    REQUIRE(p.bones[b].b.size() == 1);
    CHECK(p.bones[b].a[0].joint == l.bones[b].first);
    CHECK(p.bones[b].b[0].joint == l.bones[b].second);
  }
  const PcpBone& torso = p.bones[9];
  CHECK(torso.name == "torso");
  REQUIRE(torso.a.size() == 2);
  CHECK(torso.a[0].joint == J("l_hip"));
  CHECK(torso.a[1].joint == J("r_hip"));
  CHECK(torso.a[0].weight == 0.5);
  CHECK(torso.b[0].joint == J("head_bottom"));
  REQUIRE(p.groups.size() == 6);
  CHECK(p.groups[2].name == "upper_arms");
  CHECK(p.groups[2].bones == std::vector<int>{5, 6});
  // The plain layout protocol lists the same nine bones.
  const PcpProtocol plain = LayoutPcpProtocol(core::KeypointLayoutId::kShelf14);
  REQUIRE(plain.bones.size() == 9);
  CHECK(plain.bones[8].name == "head_bottom-head_top");
}

TEST_CASE("A bone exactly on the alpha boundary is correct, just above it is wrong", "[unit]") {
  // One bone 0 -> 1 of GT length 2: the threshold is alpha * 2 = 1. Endpoint errors 0.75 and
  // 1.25 average exactly 1.0 (all values exact in binary) -> correct; adding 2^-20 to the second
  // error -> wrong.
  PcpProtocol protocol;
  protocol.name = "one";
  protocol.bones = {PcpBone::Between("bone", 0, 1)};
  EvalObject g = testing::At(0, 0, 0);
  g.joints = {Vec3(0, 0, 0), Vec3(2, 0, 0)};
  EvalObject p = testing::At(9, 0, 0);
  p.joints = {Vec3(0, 0.75, 0), Vec3(2, 0, 1.25)};
  const EvalSequence gt = testing::Sequence({{0, {g}}});
  const PcpResult at = EvaluatePcp(gt, testing::Sequence({{0, {p}}}), protocol, PcpOptions{});
  REQUIRE(at.valid);
  REQUIRE(at.actors.size() == 1);
  CHECK(at.actors[0].correct_parts == 1);
  CHECK(at.actors[0].total_parts == 1);
  CHECK(at.average_pcp == 1.0);

  p.joints[1] = Vec3(2, 0, 1.25 + std::ldexp(1.0, -20));
  const PcpResult above = EvaluatePcp(gt, testing::Sequence({{0, {p}}}), protocol, PcpOptions{});
  REQUIRE(above.valid);
  CHECK(above.actors[0].correct_parts == 0);
  CHECK(above.actors[0].total_parts == 1);
  CHECK(above.average_pcp == 0.0);

  // alpha scales the threshold: with alpha = 0.6 the same prediction is correct again.
  PcpOptions wide;
  wide.alpha = 0.6;
  CHECK(EvaluatePcp(gt, testing::Sequence({{0, {p}}}), protocol, wide).average_pcp == 1.0);
}

TEST_CASE("A frame without a prediction counts every bone wrong", "[unit]") {
  // Actor 0 in frames 0..3. Predictions: exact in frames 0 and 1, none in frame 2, and in frame
  // 3 one sharing no valid joint with the GT (cannot be selected either).
  EvalSequence gt;
  EvalSequence pred;
  for (FrameIndex f = 0; f < 4; ++f) testing::Add(&gt, f, Person(0, 1.0, 1.0));
  testing::Add(&pred, 0, Person(5, 1.0, 1.0));
  testing::Add(&pred, 1, Person(5, 1.0, 1.0));
  EvalObject empty = testing::At(5, 1.0, 1.0);
  empty.joints.assign(14, std::nullopt);
  testing::Add(&pred, 3, empty);
  const PcpResult r = EvaluatePcp(gt, pred, ShelfCampusPcpProtocol(), PcpOptions{});
  REQUIRE(r.valid);
  REQUIRE(r.actors.size() == 1);
  const PcpActorResult& a = r.actors[0];
  // 4 frames x 10 parts scored, 2 x 10 correct -> PCP 0.5.
  CHECK(a.num_frames == 4);
  CHECK(a.num_frames_without_prediction == 2);
  CHECK(a.total_parts == 40);
  CHECK(a.correct_parts == 20);
  CHECK(a.pcp == 0.5);
  for (std::size_t b = 0; b < 10; ++b) {
    CHECK(a.bone_total[b] == 4);
    CHECK(a.bone_correct[b] == 2);
  }
  // Recall: 2 of 4 actor-frames have a selected prediction within 0.5 m.
  CHECK(r.recall_total == 4);
  CHECK(r.recall_matched == 2);
  CHECK(r.recall == 0.5);
}

TEST_CASE("PCP is averaged over the requested actors", "[unit]") {
  // Frames 0..1, actors 0 (x = 0), 1 (x = 3), 2 (x = 6), 3 (x = 9).
  //  - actor 0: exact prediction in both frames               -> 20/20 = 1.0
  //  - actor 1: exact in frame 0, none near it in frame 1     -> 10/20 = 0.5
  //  - actor 2: no prediction near it; the nearest one (3 m away) is still selected, as the
  //    protocol has no distance gate, and every part is wrong        -> 0/20 = 0.0
  //  - actor 3: exact in both frames, but not requested.
  // Average over {0, 1, 2} = (1.0 + 0.5 + 0.0) / 3 = 0.5.
  EvalSequence gt;
  EvalSequence pred;
  for (FrameIndex f = 0; f < 2; ++f) {
    for (int k = 0; k < 4; ++k) testing::Add(&gt, f, Person(k, 3.0 * k, 0.0));
    testing::Add(&pred, f, Person(100, 0.0, 0.0));
    if (f == 0) testing::Add(&pred, f, Person(101, 3.0, 0.0));
    testing::Add(&pred, f, Person(103, 9.0, 0.0));
  }
  PcpOptions options;
  options.actor_ids = {0, 1, 2};
  const PcpResult r = EvaluatePcp(gt, pred, ShelfCampusPcpProtocol(), options);
  REQUIRE(r.valid);
  REQUIRE(r.actors.size() == 3);
  CHECK(r.actors[0].actor_id == 0);
  CHECK(r.actors[0].pcp == 1.0);
  CHECK(r.actors[1].pcp == 0.5);
  CHECK(r.actors[2].pcp == 0.0);
  CHECK(r.actors[2].num_frames_without_prediction == 0);
  CHECK(r.average_pcp == Approx(0.5));
  // Group PCP follows the same per-actor pattern for every group.
  REQUIRE(r.average_group_pcp.size() == 6);
  for (const double g : r.average_group_pcp) CHECK(g == Approx(0.5));
  CHECK(r.protocol.find("Actors: 0, 1, 2.") != std::string::npos);

  SECTION("all GT ids when no actors are requested") {
    const PcpResult all = EvaluatePcp(gt, pred, ShelfCampusPcpProtocol(), PcpOptions{});
    REQUIRE(all.actors.size() == 4);
    CHECK(all.actors[3].pcp == 1.0);
    CHECK(all.average_pcp == Approx((1.0 + 0.5 + 0.0 + 1.0) / 4.0));
  }
  SECTION("an actor that never appears is reported but left out of the average") {
    PcpOptions with_absent = options;
    with_absent.actor_ids = {0, 1, 2, 42};
    const PcpResult ab = EvaluatePcp(gt, pred, ShelfCampusPcpProtocol(), with_absent);
    REQUIRE(ab.actors.size() == 4);
    CHECK(ab.actors[3].num_frames == 0);
    CHECK(std::isnan(ab.actors[3].pcp));
    CHECK(ab.average_pcp == Approx(0.5));
  }
}

TEST_CASE("The derived torso endpoint and per-group PCP", "[unit]") {
  // The prediction moves the left hip +0.3 m and the right hip -0.3 m along x: the hip midpoint
  // is unchanged, so the torso (hip midpoint -> head_bottom) stays exact and correct.
  // Upper legs (knee -> hip, GT length 0.45, threshold 0.225): endpoint errors 0 and 0.3 ->
  // mean 0.15 -> correct. Now move the hips 0.5 m instead: mean 0.25 > 0.225 -> both upper
  // legs wrong, torso still correct.
  const EvalSequence gt = testing::Sequence({{0, {Person(0, 0.0, 0.0)}}});
  for (const double shift : {0.3, 0.5}) {
    EvalObject p = Person(1, 0.0, 0.0);
    *p.joints[static_cast<std::size_t>(J("l_hip"))] += Vec3(shift, 0, 0);
    *p.joints[static_cast<std::size_t>(J("r_hip"))] -= Vec3(shift, 0, 0);
    const PcpResult r =
        EvaluatePcp(gt, testing::Sequence({{0, {p}}}), ShelfCampusPcpProtocol(), PcpOptions{});
    REQUIRE(r.valid);
    const PcpActorResult& a = r.actors[0];
    INFO("shift " << shift);
    CHECK(a.bone_correct[9] == 1);  // torso
    const std::int64_t legs = shift < 0.4 ? 1 : 0;
    CHECK(a.bone_correct[1] == legs);  // r_upper_leg
    CHECK(a.bone_correct[2] == legs);  // l_upper_leg
    CHECK(a.correct_parts == 8 + 2 * legs);
    // Groups: head, torso, upper_arms, lower_arms, upper_legs, lower_legs.
    CHECK(a.group_pcp[1] == 1.0);
    CHECK(a.group_pcp[4] == static_cast<double>(legs));
    CHECK(a.group_pcp[5] == 1.0);
  }
  SECTION("a missing predicted hip makes the torso wrong") {
    EvalObject p = Person(1, 0.0, 0.0);
    p.joints[static_cast<std::size_t>(J("l_hip"))] = std::nullopt;
    const PcpResult r =
        EvaluatePcp(gt, testing::Sequence({{0, {p}}}), ShelfCampusPcpProtocol(), PcpOptions{});
    // Torso and left upper leg lose an endpoint: 8 of 10 correct.
    CHECK(r.actors[0].bone_correct[9] == 0);
    CHECK(r.actors[0].bone_correct[2] == 0);
    CHECK(r.actors[0].correct_parts == 8);
    CHECK(r.actors[0].total_parts == 10);
  }
  SECTION("a missing GT joint removes its parts from the count") {
    EvalObject g = Person(0, 0.0, 0.0);
    g.joints[static_cast<std::size_t>(J("head_top"))] = std::nullopt;
    const PcpResult r = EvaluatePcp(testing::Sequence({{0, {g}}}),
                                    testing::Sequence({{0, {Person(1, 0.0, 0.0)}}}),
                                    ShelfCampusPcpProtocol(),
                                    PcpOptions{});
    CHECK(r.actors[0].bone_total[8] == 0);
    CHECK(r.actors[0].total_parts == 9);
    CHECK(r.actors[0].pcp == 1.0);
    CHECK(std::isnan(r.actors[0].group_pcp[0]));  // head never scored
  }
}

TEST_CASE("The prediction with the smallest mean joint error is selected", "[unit]") {
  // Two predictions near actor 0: id 3 is 0.2 m off on every joint, id 8 is exact. The exact
  // one must be selected even though it has the larger id and comes first in the input.
  const EvalSequence gt = testing::Sequence({{0, {Person(0, 0.0, 0.0)}}});
  const EvalSequence pred = testing::Sequence({{0, {Person(8, 0.0, 0.0), Person(3, 0.0, 0.2)}}});
  // Person(3, 0, 0.2) is 0.2 m off on every joint: the 0.45 m legs tolerate 0.225 m, but the
  // 0.25 m head and lower arms only 0.125 m -> if id 3 were selected, those parts would fail.
  const PcpResult r = EvaluatePcp(gt, pred, ShelfCampusPcpProtocol(), PcpOptions{});
  REQUIRE(r.valid);
  CHECK(r.actors[0].pcp == 1.0);
  const PcpResult only_far = EvaluatePcp(
      gt, testing::Sequence({{0, {Person(3, 0.0, 0.2)}}}), ShelfCampusPcpProtocol(), PcpOptions{});
  CHECK(only_far.actors[0].pcp < 1.0);
}

TEST_CASE("Frame ranges restrict the scored frames", "[unit]") {
  // Actor 0 in frames 0..9, exact predictions only in frames 4..6 (like Shelf's 300..600).
  EvalSequence gt;
  EvalSequence pred;
  for (FrameIndex f = 0; f < 10; ++f) {
    testing::Add(&gt, f, Person(0, 0.0, 0.0));
    if (f >= 4 && f <= 6) testing::Add(&pred, f, Person(1, 0.0, 0.0));
  }
  PcpOptions options;
  options.frame_ranges = {{4, 6}};
  const PcpResult r = EvaluatePcp(gt, pred, ShelfCampusPcpProtocol(), options);
  REQUIRE(r.valid);
  CHECK(r.actors[0].num_frames == 3);
  CHECK(r.actors[0].pcp == 1.0);
  CHECK(r.protocol.find("[4, 6] (3 GT frames scored)") != std::string::npos);
  const PcpResult all = EvaluatePcp(gt, pred, ShelfCampusPcpProtocol(), PcpOptions{});
  CHECK(all.actors[0].pcp == Approx(0.3));
}

TEST_CASE("PCP rejects bad protocols and options", "[unit]") {
  const EvalSequence gt = testing::Sequence({{0, {Person(0, 0.0, 0.0)}}});
  PcpProtocol bad;
  bad.name = "bad";
  bad.bones = {PcpBone::Between("b", 0, 14)};
  PcpResult r = EvaluatePcp(gt, gt, bad, PcpOptions{});
  CHECK_FALSE(r.valid);
  CHECK(r.error.find("outside [0, 14)") != std::string::npos);
  bad.bones = {PcpBone::Between("b", 0, 1)};
  bad.bones[0].a = {{0, 0.5}, {1, 0.4}};
  CHECK_FALSE(EvaluatePcp(gt, gt, bad, PcpOptions{}).valid);
  PcpOptions options;
  options.alpha = -1.0;
  CHECK_FALSE(EvaluatePcp(gt, gt, ShelfCampusPcpProtocol(), options).valid);
  options = PcpOptions{};
  options.actor_ids = {1, 1};
  CHECK_FALSE(EvaluatePcp(gt, gt, ShelfCampusPcpProtocol(), options).valid);
  // Footprint-only data has no joints for the parts.
  const EvalSequence boxes = testing::Sequence({{0, {testing::At(0, 0, 0)}}});
  CHECK_FALSE(EvaluatePcp(boxes, boxes, ShelfCampusPcpProtocol(), PcpOptions{}).valid);
}

}  // namespace
}  // namespace mvtrack::eval
