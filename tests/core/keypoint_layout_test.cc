#include "core/keypoint_layout.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <map>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace mvtrack::core {
namespace {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

const std::vector<KeypointLayoutId> kAllWithNone = {KeypointLayoutId::kNone,
                                                    KeypointLayoutId::kCoco17,
                                                    KeypointLayoutId::kBody25,
                                                    KeypointLayoutId::kShelf14,
                                                    KeypointLayoutId::kPanoptic19};

int IndexOf(const KeypointLayout& layout, const std::string& name) {
  for (int i = 0; i < layout.num_joints(); ++i) {
    if (layout.joints[static_cast<std::size_t>(i)] == name) return i;
  }
  return -1;
}

// A synthetic standing person, world frame z up, metres, built from body geometry: the named
// joints of every layout. The head is built so that the top of the head lies on the line from
// the shoulder midpoint through the ear midpoint, at 1.5 times the shoulder-to-ear distance
// (the geometric assumption behind the documented head_top rule). The skeleton's own
// head_bottom (Shelf's annotated "bottom head") sits 2 cm in front of the point the
// head_bottom rule derives, as an annotation does not coincide with the rule.
std::map<std::string, Vec3> SyntheticSkeleton(std::mt19937* rng) {
  std::uniform_real_distribution<double> jitter(-0.03, 0.03);
  auto j = [&]() { return Vec3(jitter(*rng), jitter(*rng), jitter(*rng)); };
  std::map<std::string, Vec3> s;
  const double half_shoulder = 0.19;
  const double half_hip = 0.11;
  s["l_shoulder"] = Vec3(0.0, half_shoulder, 1.45) + j();
  s["r_shoulder"] = Vec3(0.0, -half_shoulder, 1.45) + j();
  s["l_elbow"] = Vec3(0.02, 0.24, 1.17) + j();
  s["r_elbow"] = Vec3(0.02, -0.24, 1.17) + j();
  s["l_wrist"] = Vec3(0.10, 0.25, 0.93) + j();
  s["r_wrist"] = Vec3(0.10, -0.25, 0.93) + j();
  s["l_hip"] = Vec3(0.0, half_hip, 0.95) + j();
  s["r_hip"] = Vec3(0.0, -half_hip, 0.95) + j();
  s["l_knee"] = Vec3(0.03, 0.11, 0.52) + j();
  s["r_knee"] = Vec3(0.03, -0.11, 0.52) + j();
  s["l_ankle"] = Vec3(0.0, 0.11, 0.08) + j();
  s["r_ankle"] = Vec3(0.0, -0.11, 0.08) + j();
  s["l_heel"] = s["l_ankle"] + Vec3(-0.05, 0.0, -0.06);
  s["r_heel"] = s["r_ankle"] + Vec3(-0.05, 0.0, -0.06);
  s["l_big_toe"] = s["l_ankle"] + Vec3(0.18, -0.02, -0.07);
  s["r_big_toe"] = s["r_ankle"] + Vec3(0.18, 0.02, -0.07);
  s["l_small_toe"] = s["l_ankle"] + Vec3(0.16, 0.04, -0.07);
  s["r_small_toe"] = s["r_ankle"] + Vec3(0.16, -0.04, -0.07);
  // Native neck and mid_hip are deliberately NOT the midpoints, so a test can tell a copied
  // joint from a derived one.
  const Vec3 shoulder_mid = 0.5 * (s["l_shoulder"] + s["r_shoulder"]);
  s["neck"] = shoulder_mid + Vec3(0.01, 0.0, 0.04);
  s["mid_hip"] = 0.5 * (s["l_hip"] + s["r_hip"]) + Vec3(-0.01, 0.0, 0.02);
  const Vec3 ear_mid = shoulder_mid + Vec3(0.01, 0.0, 0.17) + j();
  const Vec3 lateral(0.0, 0.075, 0.0);
  s["l_ear"] = ear_mid + lateral;
  s["r_ear"] = ear_mid - lateral;
  s["l_eye"] = ear_mid + Vec3(0.09, 0.035, 0.01);
  s["r_eye"] = ear_mid + Vec3(0.09, -0.035, 0.01);
  s["nose"] = ear_mid + Vec3(0.11, 0.0, -0.03);
  s["head_top"] = shoulder_mid + 1.5 * (ear_mid - shoulder_mid);
  s["head_bottom"] = 0.5 * (shoulder_mid + ear_mid) + Vec3(0.02, 0.0, 0.0);
  return s;
}

// The head_bottom rule evaluated on `skel`'s own shoulders and ears: halfway between the
// shoulder midpoint and the ear midpoint.
Vec3 RuleHeadBottom(const std::map<std::string, Vec3>& skel) {
  const Vec3 shoulder_mid = 0.5 * (skel.at("l_shoulder") + skel.at("r_shoulder"));
  const Vec3 ear_mid = 0.5 * (skel.at("l_ear") + skel.at("r_ear"));
  return 0.5 * (shoulder_mid + ear_mid);
}

template <typename Point>
std::vector<Point> PointsFor(const KeypointLayout& layout,
                             const std::map<std::string, Point>& skeleton) {
  std::vector<Point> points;
  for (const std::string& name : layout.joints) points.push_back(skeleton.at(name));
  return points;
}

TEST_CASE("layouts have the documented joint counts and orders", "[unit]") {
  const std::vector<std::string> coco17 = {"nose",
                                           "l_eye",
                                           "r_eye",
                                           "l_ear",
                                           "r_ear",
                                           "l_shoulder",
                                           "r_shoulder",
                                           "l_elbow",
                                           "r_elbow",
                                           "l_wrist",
                                           "r_wrist",
                                           "l_hip",
                                           "r_hip",
                                           "l_knee",
                                           "r_knee",
                                           "l_ankle",
                                           "r_ankle"};
  const std::vector<std::string> body25 = {
      "nose",    "neck",      "r_shoulder",  "r_elbow", "r_wrist", "l_shoulder", "l_elbow",
      "l_wrist", "mid_hip",   "r_hip",       "r_knee",  "r_ankle", "l_hip",      "l_knee",
      "l_ankle", "r_eye",     "l_eye",       "r_ear",   "l_ear",   "l_big_toe",  "l_small_toe",
      "l_heel",  "r_big_toe", "r_small_toe", "r_heel"};
  const std::vector<std::string> shelf14 = {"r_ankle",
                                            "r_knee",
                                            "r_hip",
                                            "l_hip",
                                            "l_knee",
                                            "l_ankle",
                                            "r_wrist",
                                            "r_elbow",
                                            "r_shoulder",
                                            "l_shoulder",
                                            "l_elbow",
                                            "l_wrist",
                                            "head_bottom",
                                            "head_top"};
  const std::vector<std::string> panoptic19 = {"neck",
                                               "nose",
                                               "mid_hip",
                                               "l_shoulder",
                                               "l_elbow",
                                               "l_wrist",
                                               "l_hip",
                                               "l_knee",
                                               "l_ankle",
                                               "r_shoulder",
                                               "r_elbow",
                                               "r_wrist",
                                               "r_hip",
                                               "r_knee",
                                               "r_ankle",
                                               "l_eye",
                                               "l_ear",
                                               "r_eye",
                                               "r_ear"};

  CHECK(GetKeypointLayout(KeypointLayoutId::kCoco17).joints == coco17);
  CHECK(GetKeypointLayout(KeypointLayoutId::kBody25).joints == body25);
  CHECK(GetKeypointLayout(KeypointLayoutId::kShelf14).joints == shelf14);
  CHECK(GetKeypointLayout(KeypointLayoutId::kPanoptic19).joints == panoptic19);
  CHECK(GetKeypointLayout(KeypointLayoutId::kCoco17).num_joints() == 17);
  CHECK(GetKeypointLayout(KeypointLayoutId::kBody25).num_joints() == 25);
  CHECK(GetKeypointLayout(KeypointLayoutId::kShelf14).num_joints() == 14);
  CHECK(GetKeypointLayout(KeypointLayoutId::kPanoptic19).num_joints() == 19);
  CHECK(GetKeypointLayout(KeypointLayoutId::kNone).num_joints() == 0);
  CHECK(GetKeypointLayout(KeypointLayoutId::kNone).bones.empty());
}

TEST_CASE("every layout's table entry is consistent", "[unit]") {
  for (KeypointLayoutId id : kAllWithNone) {
    const KeypointLayout& layout = GetKeypointLayout(id);
    INFO("layout " << layout.name);
    CHECK(layout.id == id);
    // Names are unique and canonical snake_case.
    std::set<std::string> names(layout.joints.begin(), layout.joints.end());
    CHECK(names.size() == layout.joints.size());
    for (const std::string& name : layout.joints) {
      INFO("joint " << name);
      REQUIRE_FALSE(name.empty());
      for (char c : name) CHECK(((c >= 'a' && c <= 'z') || c == '_'));
    }
    // Bones are in range, not self-loops and not repeated (in either direction).
    std::set<std::pair<int, int>> seen;
    for (const auto& [a, b] : layout.bones) {
      CHECK(a >= 0);
      CHECK(b >= 0);
      CHECK(a < layout.num_joints());
      CHECK(b < layout.num_joints());
      CHECK(a != b);
      CHECK(seen.insert({std::min(a, b), std::max(a, b)}).second);
    }
  }
}

TEST_CASE("bones connect every joint into one skeleton", "[unit]") {
  // Shelf14 is the exception: its bones are the nine PCP parts, which leave the limbs and the
  // head as separate pieces (the torso is scored from derived points by the evaluator).
  for (KeypointLayoutId id :
       {KeypointLayoutId::kCoco17, KeypointLayoutId::kBody25, KeypointLayoutId::kPanoptic19}) {
    const KeypointLayout& layout = GetKeypointLayout(id);
    INFO("layout " << layout.name);
    // Union-find over the bones.
    std::vector<int> parent(static_cast<std::size_t>(layout.num_joints()));
    for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
    auto find = [&](int x) {
      while (parent[static_cast<std::size_t>(x)] != x) x = parent[static_cast<std::size_t>(x)];
      return x;
    };
    for (const auto& [a, b] : layout.bones) parent[static_cast<std::size_t>(find(a))] = find(b);
    std::set<int> roots;
    for (int j = 0; j < layout.num_joints(); ++j) roots.insert(find(j));
    CHECK(roots.size() == 1);
  }
  // BODY25 and Panoptic draw a tree (one bone fewer than joints); COCO has the face and
  // hip/shoulder cycles of its annotation skeleton.
  CHECK(GetKeypointLayout(KeypointLayoutId::kBody25).bones.size() == 24);
  CHECK(GetKeypointLayout(KeypointLayoutId::kCoco17).bones.size() == 19);
  CHECK(GetKeypointLayout(KeypointLayoutId::kPanoptic19).bones.size() == 18);
}

TEST_CASE("bones join the named limbs", "[unit]") {
  // Spot checks by name so a shifted index in the table is caught.
  auto has_bone = [](KeypointLayoutId id, const std::string& a, const std::string& b) {
    const KeypointLayout& layout = GetKeypointLayout(id);
    const int ia = IndexOf(layout, a);
    const int ib = IndexOf(layout, b);
    for (const auto& [x, y] : layout.bones) {
      if ((x == ia && y == ib) || (x == ib && y == ia)) return true;
    }
    return false;
  };
  for (KeypointLayoutId id : AllKeypointLayouts()) {
    INFO("layout " << GetKeypointLayout(id).name);
    CHECK(has_bone(id, "l_knee", "l_ankle"));
    CHECK(has_bone(id, "r_knee", "r_ankle"));
    CHECK(has_bone(id, "l_hip", "l_knee"));
    CHECK(has_bone(id, "r_hip", "r_knee"));
    CHECK(has_bone(id, "l_elbow", "l_wrist"));
    CHECK(has_bone(id, "r_elbow", "r_wrist"));
    CHECK(has_bone(id, "l_shoulder", "l_elbow"));
    CHECK(has_bone(id, "r_shoulder", "r_elbow"));
    CHECK_FALSE(has_bone(id, "l_knee", "r_ankle"));
  }
  // Shelf: exactly the nine PCP parts; the torso is scored by the evaluator.
  CHECK(GetKeypointLayout(KeypointLayoutId::kShelf14).bones.size() == 9);
  CHECK(has_bone(KeypointLayoutId::kShelf14, "head_bottom", "head_top"));
  // Shelf's joint 12 is the bottom of the head, not a neck; only Shelf has a head_bottom.
  CHECK(IndexOf(GetKeypointLayout(KeypointLayoutId::kShelf14), "neck") == -1);
  for (KeypointLayoutId id : AllKeypointLayouts()) {
    const int expected = id == KeypointLayoutId::kShelf14 ? 12 : -1;
    CHECK(IndexOf(GetKeypointLayout(id), "head_bottom") == expected);
  }
  CHECK(has_bone(KeypointLayoutId::kBody25, "l_ankle", "l_heel"));
  CHECK(has_bone(KeypointLayoutId::kBody25, "neck", "mid_hip"));
  CHECK(has_bone(KeypointLayoutId::kPanoptic19, "neck", "mid_hip"));
  CHECK(has_bone(KeypointLayoutId::kCoco17, "l_shoulder", "l_hip"));
}

TEST_CASE("layout names parse, including the campus14 alias", "[unit]") {
  for (KeypointLayoutId id : kAllWithNone) {
    const auto parsed = KeypointLayoutFromName(GetKeypointLayout(id).name);
    REQUIRE(parsed.has_value());
    CHECK(*parsed == id);
  }
  CHECK(KeypointLayoutFromName("coco17") == KeypointLayoutId::kCoco17);
  CHECK(KeypointLayoutFromName("body25") == KeypointLayoutId::kBody25);
  CHECK(KeypointLayoutFromName("shelf14") == KeypointLayoutId::kShelf14);
  CHECK(KeypointLayoutFromName("campus14") == KeypointLayoutId::kShelf14);
  CHECK(KeypointLayoutFromName("panoptic19") == KeypointLayoutId::kPanoptic19);
  CHECK(KeypointLayoutFromName("none") == KeypointLayoutId::kNone);
  CHECK_FALSE(KeypointLayoutFromName("").has_value());
  CHECK_FALSE(KeypointLayoutFromName("coco").has_value());
  CHECK_FALSE(KeypointLayoutFromName("COCO17").has_value());
  CHECK_FALSE(KeypointLayoutFromName("coco17 ").has_value());
  CHECK_FALSE(KeypointLayoutFromName("h36m17").has_value());

  const std::vector<KeypointLayoutId> all = AllKeypointLayouts();
  CHECK(all.size() == 4);
  CHECK(std::set<KeypointLayoutId>(all.begin(), all.end()).size() == 4);
  CHECK(std::find(all.begin(), all.end(), KeypointLayoutId::kNone) == all.end());
}

TEST_CASE("every mapping is affine and in range", "[unit]") {
  for (KeypointLayoutId from : kAllWithNone) {
    for (KeypointLayoutId to : kAllWithNone) {
      const KeypointMapping m = MakeKeypointMapping(from, to);
      INFO(GetKeypointLayout(from).name << " -> " << GetKeypointLayout(to).name);
      CHECK(m.from == from);
      CHECK(m.to == to);
      REQUIRE(m.targets.size() == GetKeypointLayout(to).joints.size());
      for (const auto& sources : m.targets) {
        if (sources.empty()) continue;
        double sum = 0.0;
        for (const JointSource& s : sources) {
          CHECK(s.source_joint >= 0);
          CHECK(s.source_joint < GetKeypointLayout(from).num_joints());
          sum += s.weight;
        }
        CHECK(sum == Approx(1.0).margin(1e-12));
      }
    }
  }
}

TEST_CASE("identity mapping is the identity", "[unit]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  for (KeypointLayoutId id : AllKeypointLayouts()) {
    const KeypointMapping m = MakeKeypointMapping(id, id);
    const int n = GetKeypointLayout(id).num_joints();
    for (int j = 0; j < n; ++j) {
      const auto& sources = m.targets[static_cast<std::size_t>(j)];
      REQUIRE(sources.size() == 1);
      CHECK(sources[0].source_joint == j);
      CHECK(sources[0].weight == 1.0);
    }
    std::vector<Vec3> points;
    std::vector<bool> valid;
    for (int j = 0; j < n; ++j) {
      points.emplace_back(u(rng), u(rng), u(rng));
      valid.push_back(j % 3 != 1);
    }
    std::vector<Vec3> out;
    std::vector<bool> out_valid;
    ApplyKeypointMapping(m, points, valid, &out, &out_valid);
    CHECK(out_valid == valid);
    for (int j = 0; j < n; ++j) {
      if (valid[static_cast<std::size_t>(j)]) {
        CHECK(out[static_cast<std::size_t>(j)] == points[static_cast<std::size_t>(j)]);
      }
    }
  }
}

TEST_CASE("COCO17 -> Shelf14 on a synthetic 3D skeleton", "[unit]") {
  std::mt19937 rng(20240611);
  const auto& coco = GetKeypointLayout(KeypointLayoutId::kCoco17);
  const auto& shelf = GetKeypointLayout(KeypointLayoutId::kShelf14);
  const KeypointMapping m =
      MakeKeypointMapping(KeypointLayoutId::kCoco17, KeypointLayoutId::kShelf14);
  for (int trial = 0; trial < 20; ++trial) {
    const auto skel = SyntheticSkeleton(&rng);
    const std::vector<Vec3> in = PointsFor(coco, skel);
    std::vector<Vec3> out;
    std::vector<bool> out_valid;
    ApplyKeypointMapping(m, in, std::vector<bool>(in.size(), true), &out, &out_valid);
    REQUIRE(out.size() == 14);
    for (int j = 0; j < 14; ++j) {
      const std::string& name = shelf.joints[static_cast<std::size_t>(j)];
      INFO("joint " << name);
      CHECK(out_valid[static_cast<std::size_t>(j)]);
      if (name == "head_bottom") {
        CHECK((out[12] - RuleHeadBottom(skel)).norm() < 1e-12);
        // Derived, not the skeleton's own (offset) head_bottom, and not the shoulder midpoint
        // or the neck: it lies halfway up to the ears (>= 7 cm above the shoulder midpoint).
        CHECK((out[12] - skel.at("head_bottom")).norm() > 0.015);
        const Vec3 shoulder_mid = 0.5 * (skel.at("l_shoulder") + skel.at("r_shoulder"));
        CHECK((out[12] - shoulder_mid).norm() > 0.05);
        CHECK((out[12] - skel.at("neck")).norm() > 0.01);
      } else if (name == "head_top") {
        CHECK((out[13] - skel.at("head_top")).norm() < 1e-12);
      } else {
        // Shared joints are copied bit for bit.
        CHECK(out[static_cast<std::size_t>(j)] == skel.at(name));
      }
    }
  }
}

TEST_CASE("mappings commute with rigid motions", "[unit]") {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (KeypointLayoutId from : AllKeypointLayouts()) {
    for (KeypointLayoutId to : AllKeypointLayouts()) {
      const KeypointMapping m = MakeKeypointMapping(from, to);
      const auto skel = SyntheticSkeleton(&rng);
      const Eigen::Quaterniond q = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
      const Vec3 t(3.0 * u(rng), 3.0 * u(rng), 3.0 * u(rng));
      std::map<std::string, Vec3> moved;
      for (const auto& [name, p] : skel) moved[name] = q * p + t;
      const auto& src = GetKeypointLayout(from);
      const std::vector<bool> all_valid(static_cast<std::size_t>(src.num_joints()), true);
      std::vector<Vec3> a, b;
      std::vector<bool> va, vb;
      ApplyKeypointMapping(m, PointsFor(src, skel), all_valid, &a, &va);
      ApplyKeypointMapping(m, PointsFor(src, moved), all_valid, &b, &vb);
      CHECK(va == vb);
      for (std::size_t j = 0; j < a.size(); ++j) {
        if (va[j]) CHECK((q * a[j] + t - b[j]).norm() < 1e-9);
      }
    }
  }
}

TEST_CASE("COCO17 -> BODY25 / Panoptic19 derive neck and mid_hip as midpoints", "[unit]") {
  std::mt19937 rng(3);
  const auto skel = SyntheticSkeleton(&rng);
  const auto& coco = GetKeypointLayout(KeypointLayoutId::kCoco17);
  const Vec3 shoulder_mid = 0.5 * (skel.at("l_shoulder") + skel.at("r_shoulder"));
  const Vec3 hip_mid = 0.5 * (skel.at("l_hip") + skel.at("r_hip"));
  for (KeypointLayoutId to : {KeypointLayoutId::kBody25, KeypointLayoutId::kPanoptic19}) {
    const auto& target = GetKeypointLayout(to);
    INFO("target " << target.name);
    const KeypointMapping m = MakeKeypointMapping(KeypointLayoutId::kCoco17, to);
    std::vector<Vec3> out;
    std::vector<bool> valid;
    ApplyKeypointMapping(m, PointsFor(coco, skel), std::vector<bool>(17, true), &out, &valid);
    const auto neck = static_cast<std::size_t>(IndexOf(target, "neck"));
    const auto mid_hip = static_cast<std::size_t>(IndexOf(target, "mid_hip"));
    CHECK(valid[neck]);
    CHECK(valid[mid_hip]);
    CHECK((out[neck] - shoulder_mid).norm() < 1e-12);
    CHECK((out[mid_hip] - hip_mid).norm() < 1e-12);
    for (std::size_t j = 0; j < out.size(); ++j) {
      const std::string& name = target.joints[j];
      if (name == "neck" || name == "mid_hip") continue;
      // Every other target joint is either a COCO joint (copied) or underivable (feet).
      if (IndexOf(coco, name) >= 0) {
        CHECK(valid[j]);
        CHECK(out[j] == skel.at(name));
      } else {
        CHECK_FALSE(valid[j]);
        CHECK(m.targets[j].empty());
      }
    }
  }
}

TEST_CASE("head_bottom and neck are distinct joints in both directions", "[unit]") {
  std::mt19937 rng(5);
  const auto skel = SyntheticSkeleton(&rng);
  const Vec3 shoulder_mid = 0.5 * (skel.at("l_shoulder") + skel.at("r_shoulder"));
  // BODY25 and Panoptic have their own neck but no head_bottom: Shelf's joint 12 comes from the
  // shoulders and ears (the rule), never from their neck.
  for (KeypointLayoutId from : {KeypointLayoutId::kBody25, KeypointLayoutId::kPanoptic19}) {
    const auto& src = GetKeypointLayout(from);
    INFO("from " << src.name);
    const KeypointMapping m = MakeKeypointMapping(from, KeypointLayoutId::kShelf14);
    std::vector<Vec3> out;
    std::vector<bool> valid;
    ApplyKeypointMapping(m,
                         PointsFor(src, skel),
                         std::vector<bool>(static_cast<std::size_t>(src.num_joints()), true),
                         &out,
                         &valid);
    REQUIRE(valid[12]);
    CHECK((out[12] - RuleHeadBottom(skel)).norm() < 1e-12);
    const int neck_index = IndexOf(src, "neck");
    for (const JointSource& s : m.targets[12]) CHECK(s.source_joint != neck_index);
    REQUIRE(valid[13]);
    CHECK((out[13] - skel.at("head_top")).norm() < 1e-12);
  }
  // Shelf has a head_bottom but no neck: BODY25's and Panoptic's neck is the shoulder midpoint,
  // whatever Shelf's head_bottom says, and head_bottom itself has nowhere to go.
  const auto& shelf = GetKeypointLayout(KeypointLayoutId::kShelf14);
  for (KeypointLayoutId to : {KeypointLayoutId::kBody25, KeypointLayoutId::kPanoptic19}) {
    const auto& target = GetKeypointLayout(to);
    INFO("to " << target.name);
    const KeypointMapping m = MakeKeypointMapping(KeypointLayoutId::kShelf14, to);
    std::vector<Vec3> out;
    std::vector<bool> valid;
    ApplyKeypointMapping(m, PointsFor(shelf, skel), std::vector<bool>(14, true), &out, &valid);
    const auto neck = static_cast<std::size_t>(IndexOf(target, "neck"));
    REQUIRE(valid[neck]);
    CHECK((out[neck] - shoulder_mid).norm() < 1e-12);
    CHECK((out[neck] - skel.at("head_bottom")).norm() > 0.05);
    for (const auto& sources : m.targets) {
      for (const JointSource& s : sources) CHECK(s.source_joint != 12);
    }
  }
}

TEST_CASE("native joints are copied, never re-derived", "[unit]") {
  std::mt19937 rng(17);
  const auto skel = SyntheticSkeleton(&rng);
  // Shelf's own head_bottom and head_top survive Shelf -> Shelf although rules exist for both.
  const auto& shelf = GetKeypointLayout(KeypointLayoutId::kShelf14);
  {
    const KeypointMapping m =
        MakeKeypointMapping(KeypointLayoutId::kShelf14, KeypointLayoutId::kShelf14);
    std::vector<Vec3> in = PointsFor(shelf, skel);
    in[13] += Vec3(0.0, 0.0, 0.05);  // a head_top the rule would not produce
    std::vector<Vec3> out;
    std::vector<bool> valid;
    ApplyKeypointMapping(m, in, std::vector<bool>(14, true), &out, &valid);
    CHECK(out[12] == skel.at("head_bottom"));
    CHECK(out[13] == in[13]);
  }
  // BODY25 and Panoptic have their own neck and mid_hip (offset from the midpoints).
  const KeypointMapping m =
      MakeKeypointMapping(KeypointLayoutId::kBody25, KeypointLayoutId::kPanoptic19);
  const auto& body25 = GetKeypointLayout(KeypointLayoutId::kBody25);
  std::vector<Vec3> out;
  std::vector<bool> valid;
  ApplyKeypointMapping(m, PointsFor(body25, skel), std::vector<bool>(25, true), &out, &valid);
  CHECK(out[0] == skel.at("neck"));
  CHECK(out[2] == skel.at("mid_hip"));
  // Shelf has no face and no feet.
  const KeypointMapping from_shelf =
      MakeKeypointMapping(KeypointLayoutId::kShelf14, KeypointLayoutId::kBody25);
  ApplyKeypointMapping(
      from_shelf, PointsFor(shelf, skel), std::vector<bool>(14, true), &out, &valid);
  CHECK((out[8] - 0.5 * (skel.at("l_hip") + skel.at("r_hip"))).norm() < 1e-12);
  for (const char* name : {"nose", "l_eye", "r_eye", "l_ear", "r_ear", "l_heel", "r_big_toe"}) {
    INFO(name);
    CHECK_FALSE(valid[static_cast<std::size_t>(IndexOf(body25, name))]);
  }
}

TEST_CASE("round trips through BODY25 and COCO17 preserve shared joints", "[unit]") {
  std::mt19937 rng(11);
  const auto skel = SyntheticSkeleton(&rng);
  const auto& coco = GetKeypointLayout(KeypointLayoutId::kCoco17);
  const auto& body25 = GetKeypointLayout(KeypointLayoutId::kBody25);
  const KeypointMapping to_coco =
      MakeKeypointMapping(KeypointLayoutId::kBody25, KeypointLayoutId::kCoco17);
  const KeypointMapping to_body =
      MakeKeypointMapping(KeypointLayoutId::kCoco17, KeypointLayoutId::kBody25);

  SECTION("BODY25 -> COCO17 -> BODY25") {
    const std::vector<Vec3> in = PointsFor(body25, skel);
    std::vector<Vec3> mid, back;
    std::vector<bool> mid_valid, back_valid;
    ApplyKeypointMapping(to_coco, in, std::vector<bool>(25, true), &mid, &mid_valid);
    CHECK(mid_valid == std::vector<bool>(17, true));
    ApplyKeypointMapping(to_body, mid, mid_valid, &back, &back_valid);
    for (std::size_t j = 0; j < 25; ++j) {
      const std::string& name = body25.joints[j];
      INFO(name);
      if (IndexOf(coco, name) >= 0) {
        CHECK(back_valid[j]);
        CHECK(back[j] == in[j]);
      } else if (name == "neck") {
        CHECK(back_valid[j]);
        CHECK((back[j] - 0.5 * (skel.at("l_shoulder") + skel.at("r_shoulder"))).norm() < 1e-12);
      } else if (name == "mid_hip") {
        CHECK(back_valid[j]);
        CHECK((back[j] - 0.5 * (skel.at("l_hip") + skel.at("r_hip"))).norm() < 1e-12);
      } else {
        CHECK_FALSE(back_valid[j]);  // feet are lost in COCO
      }
    }
  }
  SECTION("COCO17 -> BODY25 -> COCO17 is the identity, also in 2D with missing joints") {
    std::map<std::string, Vec2> skel2d;
    for (const auto& [name, p] : skel) skel2d[name] = Vec2(p.x() * 500.0, p.z() * 500.0);
    const std::vector<Vec2> in = PointsFor(coco, skel2d);
    std::vector<bool> valid(17, true);
    valid[3] = false;   // l_ear
    valid[16] = false;  // r_ankle
    std::vector<Vec2> mid, back;
    std::vector<bool> mid_valid, back_valid;
    ApplyKeypointMapping(to_body, in, valid, &mid, &mid_valid);
    ApplyKeypointMapping(to_coco, mid, mid_valid, &back, &back_valid);
    CHECK(back_valid == valid);
    for (std::size_t j = 0; j < 17; ++j) {
      if (valid[j]) CHECK(back[j] == in[j]);
    }
  }
}

TEST_CASE("validity propagates to derived joints", "[unit]") {
  std::mt19937 rng(13);
  const auto skel = SyntheticSkeleton(&rng);
  const auto& coco = GetKeypointLayout(KeypointLayoutId::kCoco17);
  const KeypointMapping m =
      MakeKeypointMapping(KeypointLayoutId::kCoco17, KeypointLayoutId::kShelf14);
  const std::vector<Vec3> in = PointsFor(coco, skel);

  SECTION("a missing ear invalidates head_bottom and head_top only") {
    for (const char* ear : {"l_ear", "r_ear"}) {
      std::vector<bool> valid(17, true);
      valid[static_cast<std::size_t>(IndexOf(coco, ear))] = false;
      std::vector<Vec3> out;
      std::vector<bool> out_valid;
      ApplyKeypointMapping(m, in, valid, &out, &out_valid);
      std::vector<bool> expected(14, true);
      expected[12] = false;  // head_bottom
      expected[13] = false;  // head_top
      CHECK(out_valid == expected);
      CHECK(out[12] == Vec3::Zero());
      CHECK(out[13] == Vec3::Zero());
    }
  }
  SECTION("a missing shoulder invalidates that shoulder, head_bottom and head_top") {
    std::vector<bool> valid(17, true);
    valid[static_cast<std::size_t>(IndexOf(coco, "r_shoulder"))] = false;
    std::vector<Vec3> out;
    std::vector<bool> out_valid;
    ApplyKeypointMapping(m, in, valid, &out, &out_valid);
    std::vector<bool> expected(14, true);
    expected[8] = false;   // r_shoulder
    expected[12] = false;  // head_bottom
    expected[13] = false;  // head_top
    CHECK(out_valid == expected);
  }
  SECTION("from Shelf14 the neck needs both shoulders and nothing else") {
    const auto& shelf = GetKeypointLayout(KeypointLayoutId::kShelf14);
    const auto& body25 = GetKeypointLayout(KeypointLayoutId::kBody25);
    const KeypointMapping to_body =
        MakeKeypointMapping(KeypointLayoutId::kShelf14, KeypointLayoutId::kBody25);
    const auto neck = static_cast<std::size_t>(IndexOf(body25, "neck"));
    const std::vector<Vec3> shelf_points = PointsFor(shelf, skel);
    std::vector<Vec3> out;
    std::vector<bool> out_valid;
    std::vector<bool> valid(14, true);
    valid[12] = false;  // head_bottom
    valid[13] = false;  // head_top
    ApplyKeypointMapping(to_body, shelf_points, valid, &out, &out_valid);
    CHECK(out_valid[neck]);
    for (const char* shoulder : {"l_shoulder", "r_shoulder"}) {
      std::vector<bool> no_shoulder(14, true);
      no_shoulder[static_cast<std::size_t>(IndexOf(shelf, shoulder))] = false;
      ApplyKeypointMapping(to_body, shelf_points, no_shoulder, &out, &out_valid);
      CHECK_FALSE(out_valid[neck]);
    }
  }
  SECTION("face joints without a source stay invalid whatever the input") {
    const KeypointMapping back =
        MakeKeypointMapping(KeypointLayoutId::kShelf14, KeypointLayoutId::kCoco17);
    for (const char* face : {"nose", "l_eye", "r_eye", "l_ear", "r_ear"}) {
      CHECK(back.targets[static_cast<std::size_t>(IndexOf(coco, face))].empty());
    }
  }
  SECTION("too-short input counts as invalid instead of reading out of bounds") {
    std::vector<Vec3> out;
    std::vector<bool> out_valid;
    const std::vector<Vec3> shortened(in.begin(), in.begin() + 10);
    ApplyKeypointMapping(m, shortened, std::vector<bool>(10, true), &out, &out_valid);
    CHECK_FALSE(out_valid[0]);  // r_ankle is COCO joint 16
    CHECK(out_valid[8]);        // r_shoulder is COCO joint 6
  }
}

TEST_CASE("mappings from and to the box-only layout are empty", "[unit]") {
  const KeypointMapping to_none =
      MakeKeypointMapping(KeypointLayoutId::kCoco17, KeypointLayoutId::kNone);
  CHECK(to_none.targets.empty());
  const KeypointMapping from_none =
      MakeKeypointMapping(KeypointLayoutId::kNone, KeypointLayoutId::kShelf14);
  REQUIRE(from_none.targets.size() == 14);
  for (const auto& sources : from_none.targets) CHECK(sources.empty());
}

}  // namespace
}  // namespace mvtrack::core
