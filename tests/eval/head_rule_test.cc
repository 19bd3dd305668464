#include "eval/head_rule.h"

#include <catch2/catch.hpp>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace mvtrack::eval {
namespace {

using Joints = std::vector<std::optional<Vec3>>;

int Index(core::KeypointLayoutId layout, const std::string& name) {
  const auto& joints = core::GetKeypointLayout(layout).joints;
  for (std::size_t i = 0; i < joints.size(); ++i) {
    if (joints[i] == name) return static_cast<int>(i);
  }
  FAIL("no joint " << name);
  return -1;
}

void Set(Joints* joints, core::KeypointLayoutId layout, const std::string& name, const Vec3& p) {
  (*joints)[static_cast<std::size_t>(Index(layout, name))] = p;
}

// An upright person at the origin facing +y: shoulders at x = +-0.2 m (its right shoulder on +x,
// as seen by someone it faces), hips at x = +-0.1 m, neck 1.5 m, mid hip 1.0 m.
Joints UprightBody25() {
  const auto b = core::KeypointLayoutId::kBody25;
  Joints j(static_cast<std::size_t>(core::GetKeypointLayout(b).num_joints()));
  Set(&j, b, "neck", {0.0, 0.0, 1.5});
  Set(&j, b, "mid_hip", {0.0, 0.0, 1.0});
  Set(&j, b, "r_shoulder", {0.2, 0.0, 1.5});
  Set(&j, b, "l_shoulder", {-0.2, 0.0, 1.5});
  Set(&j, b, "r_hip", {0.1, 0.0, 1.0});
  Set(&j, b, "l_hip", {-0.1, 0.0, 1.0});
  Set(&j, b, "r_ear", {0.07, 0.0, 1.7});
  Set(&j, b, "l_ear", {-0.07, 0.0, 1.7});
  return j;
}

}  // namespace

TEST_CASE("Head rule names round-trip and unknown names are rejected", "[unit][eval]") {
  for (const HeadRule r : {HeadRule::kCampus, HeadRule::kShelf4da}) {
    REQUIRE(HeadRuleFromName(HeadRuleName(r)) == r);
  }
  REQUIRE_FALSE(HeadRuleFromName("4da").has_value());
  REQUIRE_FALSE(HeadRuleFromName("").has_value());
}

TEST_CASE("4D Association head top: 0.125 m along the facing direction plus 0.145 m up",
          "[unit][eval]") {
  // (neck - mid_hip) x (r_shoulder - l_shoulder) = (0, 0, 0.5) x (0.4, 0, 0) = (0, 0.2, 0).
  const Vec3 bottom(0.0, 0.0, 1.6);
  const auto top = FourDAssociationHeadTop(
      bottom, {0.0, 0.0, 1.5}, {0.0, 0.0, 1.0}, {0.2, 0.0, 1.5}, {-0.2, 0.0, 1.5});
  REQUIRE(top.has_value());
  CHECK(top->x() == Approx(0.0).margin(1e-12));
  CHECK(top->y() == Approx(0.125));
  CHECK(top->z() == Approx(1.6 + 0.145));
  // A person turned by 90 degrees faces -x: the offset turns with it.
  const auto turned = FourDAssociationHeadTop(
      bottom, {0.0, 0.0, 1.5}, {0.0, 0.0, 1.0}, {0.0, 0.2, 1.5}, {0.0, -0.2, 1.5});
  REQUIRE(turned.has_value());
  CHECK(turned->x() == Approx(-0.125));
  CHECK(turned->y() == Approx(0.0).margin(1e-12));
  // No facing direction when the spine is parallel to the shoulder line (or zero).
  CHECK_FALSE(FourDAssociationHeadTop(
                  bottom, {0.0, 0.0, 1.5}, {0.0, 0.0, 1.5}, {0.2, 0.0, 1.5}, {-0.2, 0.0, 1.5})
                  .has_value());
}

TEST_CASE("ApplyHeadRule re-derives only head_top of skeletons mapped to shelf14", "[unit][eval]") {
  const auto b25 = core::KeypointLayoutId::kBody25;
  const auto shelf = core::KeypointLayoutId::kShelf14;
  const Joints source = UprightBody25();
  const core::KeypointMapping mapping = core::MakeKeypointMapping(b25, shelf);
  Joints mapped(14);
  for (std::size_t t = 0; t < mapping.targets.size(); ++t) {
    if (mapping.targets[t].empty()) continue;
    Vec3 sum = Vec3::Zero();
    bool ok = true;
    for (const core::JointSource& s : mapping.targets[t]) {
      const auto& p = source[static_cast<std::size_t>(s.source_joint)];
      if (!p) {
        ok = false;
        break;
      }
      sum += s.weight * *p;
    }
    if (ok) mapped[t] = sum;
  }
  const auto top = static_cast<std::size_t>(Index(shelf, "head_top"));
  const auto bottom = static_cast<std::size_t>(Index(shelf, "head_bottom"));
  REQUIRE(mapped[bottom].has_value());
  REQUIRE(mapped[top].has_value());
  // head_bottom = mean(shoulder midpoint (0, 0, 1.5), ear midpoint (0, 0, 1.7)) = (0, 0, 1.6).
  CHECK(mapped[bottom]->z() == Approx(1.6));

  SECTION("campus keeps the affine rule's head_top (1.5 ear_mid - 0.5 shoulder_mid)") {
    Joints out = mapped;
    ApplyHeadRule(HeadRule::kCampus, b25, source, &out);
    REQUIRE(out[top].has_value());
    CHECK(out[top]->z() == Approx(1.8));
  }
  SECTION("shelf-4da replaces head_top and leaves every other joint alone") {
    Joints out = mapped;
    ApplyHeadRule(HeadRule::kShelf4da, b25, source, &out);
    REQUIRE(out[top].has_value());
    CHECK(out[top]->y() == Approx(0.125));
    CHECK(out[top]->z() == Approx(1.6 + 0.145));
    for (std::size_t j = 0; j < out.size(); ++j) {
      if (j != top) CHECK(out[j] == mapped[j]);
    }
  }
  SECTION("shelf-4da derives neck and mid_hip of a COCO-17 skeleton from shoulders and hips") {
    const auto coco = core::KeypointLayoutId::kCoco17;
    Joints c(17);
    Set(&c, coco, "r_shoulder", {0.2, 0.0, 1.5});
    Set(&c, coco, "l_shoulder", {-0.2, 0.0, 1.5});
    Set(&c, coco, "r_hip", {0.1, 0.0, 1.0});
    Set(&c, coco, "l_hip", {-0.1, 0.0, 1.0});
    Joints out = mapped;
    ApplyHeadRule(HeadRule::kShelf4da, coco, c, &out);
    REQUIRE(out[top].has_value());
    CHECK(out[top]->y() == Approx(0.125));
  }
  SECTION("shelf-4da without a mid hip leaves no head_top") {
    Joints partial = source;
    partial[static_cast<std::size_t>(Index(b25, "mid_hip"))].reset();
    Joints out = mapped;
    ApplyHeadRule(HeadRule::kShelf4da, b25, partial, &out);
    CHECK_FALSE(out[top].has_value());
    CHECK(out[bottom] == mapped[bottom]);
  }
  SECTION("ground truth already in shelf14 is never changed") {
    Joints gt = mapped;
    ApplyHeadRule(HeadRule::kShelf4da, shelf, mapped, &gt);
    CHECK(gt == mapped);
  }
}

}  // namespace mvtrack::eval
