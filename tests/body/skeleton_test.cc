// lib/body: bone lengths per track and the fit of one frame's joints to three views.

#include "body/skeleton.h"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "body/test_cameras.h"

namespace mvtrack::body {
namespace {

// shelf14: legs, arms and head as separate bones (r_ankle 0 ... head_top 13).
const core::KeypointLayout& Layout() {
  return core::GetKeypointLayout(core::KeypointLayoutId::kShelf14);
}

// A standing person at the origin, shelf14 order, metres.
std::vector<Vec3> Person() {
  return {{0.10, 0.0, 0.05},
          {0.10, 0.0, 0.50},
          {0.10, 0.0, 0.95},
          {-0.10, 0.0, 0.95},
          {-0.10, 0.0, 0.50},
          {-0.10, 0.0, 0.05},
          {0.25, 0.05, 0.95},
          {0.22, 0.0, 1.20},
          {0.20, 0.0, 1.45},
          {-0.20, 0.0, 1.45},
          {-0.22, 0.0, 1.20},
          {-0.25, 0.05, 0.95},
          {0.0, 0.0, 1.55},
          {0.0, 0.0, 1.80}};
}

Mat34 Camera(double azimuth) { return testing::RingCamera(azimuth); }

core::PersonView View(int camera, const Mat34& p, const std::vector<Vec3>& joints) {
  core::PersonView v;
  v.camera_index = camera;
  v.observation.scale_px = 700.0;
  for (const Vec3& j : joints) {
    const Vec3 x = p * j.homogeneous();
    v.observation.points_px.push_back(x.hnormalized());
    v.observation.confidence.push_back(0.9);
  }
  return v;
}

double Length(const std::vector<std::optional<Vec3>>& j, std::pair<int, int> bone) {
  return (*j[static_cast<std::size_t>(bone.first)] - *j[static_cast<std::size_t>(bone.second)])
      .norm();
}

}  // namespace

TEST_CASE("bone lengths: the median of a bone and its mirror image, once measured enough",
          "[unit]") {
  BoneLengths lengths(Layout());
  std::vector<std::optional<Vec3>> frame(14);
  frame[0] = Vec3(0, 0, 0.05);  // r_ankle
  frame[1] = Vec3(0, 0, 0.50);  // r_knee: r_lower_leg 0.45
  lengths.AddFrame(frame);
  lengths.Update();
  CHECK_FALSE(lengths.lengths()[0].has_value());  // one sample: not enough
  for (int i = 0; i < 3; ++i) lengths.AddFrame(frame);
  // The left lower leg (l_knee 4, l_ankle 5) measures 0.47 twice: pooled with the right one.
  std::vector<std::optional<Vec3>> left(14);
  left[4] = Vec3(0, 0, 0.52);
  left[5] = Vec3(0, 0, 0.05);
  lengths.AddFrame(left);
  lengths.AddFrame(left);
  // Implausible lengths are not samples.
  std::vector<std::optional<Vec3>> crossing(14);
  crossing[0] = Vec3(0, 0, 0);
  crossing[1] = Vec3(0, 0, 3.0);
  lengths.AddFrame(crossing);
  lengths.Update();
  const auto& bones = Layout().bones;
  // The stature the shins give (their samples over the shin's share), the median of
  // 0.45 / 0.246 x4 and 0.47 / 0.246 x2.
  const double stature = 0.45 / BoneLengths::StatureShare("r_knee", "r_ankle");
  for (std::size_t i = 0; i < bones.size(); ++i) {
    const bool lower_leg =
        bones[i] == std::pair<int, int>{0, 1} || bones[i] == std::pair<int, int>{4, 5};
    const double share = BoneLengths::StatureShare(Layout().joints[bones[i].first],
                                                   Layout().joints[bones[i].second]);
    if (lower_leg) {
      REQUIRE(lengths.lengths()[i].has_value());
      CHECK(*lengths.lengths()[i] == Approx(0.45));  // median of 0.45 x4, 0.47 x2
    } else if (share > 0.0) {
      // A limb never measured: its share of the stature, as uncertain as the share is.
      REQUIRE(lengths.lengths()[i].has_value());
      CHECK(*lengths.lengths()[i] == Approx(stature * share));
      CHECK(lengths.uncertainties()[i] ==
            Approx(BoneLengths::kShareSpread * stature * share).epsilon(0.01));
    } else {
      CHECK_FALSE(lengths.lengths()[i].has_value());  // the head: no share, no samples
    }
  }
  // Constant after kMaxSamples samples of a bone.
  std::vector<std::optional<Vec3>> longer(14);
  longer[0] = Vec3(0, 0, 0.0);
  longer[1] = Vec3(0, 0, 0.6);
  for (int i = 0; i < 2 * BoneLengths::kMaxSamples; ++i) lengths.AddFrame(longer);
  lengths.Update();
  const double settled = *lengths.lengths()[0];
  for (int i = 0; i < 100; ++i) lengths.AddFrame(frame);
  lengths.Update();
  CHECK(*lengths.lengths()[0] == settled);
}

TEST_CASE("bone lengths: a limb whose few samples scatter leans on the body's proportions",
          "[unit]") {
  // Legs and upper arms measured 60 times each, consistently, of a person 1.80 m tall; the
  // forearms (true length 0.146 x 1.80 = 0.263 m) five times, scattered around 0.40 m (a
  // badly seen arm).
  const double stature = 1.80;
  const auto share = [](const char* a, const char* b) { return BoneLengths::StatureShare(a, b); };
  BoneLengths lengths(Layout());
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 1.0);
  const auto limb = [&](std::vector<std::optional<Vec3>>* frame, int a, int b, double length) {
    (*frame)[static_cast<std::size_t>(a)] = Vec3(0, 0, 0);
    (*frame)[static_cast<std::size_t>(b)] = Vec3(0, 0, length);
  };
  for (int i = 0; i < 30; ++i) {
    std::vector<std::optional<Vec3>> frame(14);
    limb(&frame, 0, 1, stature * share("knee", "ankle") * (1.0 + 0.01 * noise(rng)));
    limb(&frame, 3, 4, stature * share("hip", "knee") * (1.0 + 0.01 * noise(rng)));
    limb(&frame, 7, 8, stature * share("shoulder", "elbow") * (1.0 + 0.01 * noise(rng)));
    lengths.AddFrame(frame);
    lengths.AddFrame(frame);
  }
  for (const double forearm : {0.30, 0.36, 0.40, 0.45, 0.52}) {
    std::vector<std::optional<Vec3>> frame(14);
    limb(&frame, 10, 11, forearm);
    lengths.AddFrame(frame);
  }
  lengths.Update();
  const auto& bones = Layout().bones;
  for (std::size_t i = 0; i < bones.size(); ++i) {
    const std::string a = Layout().joints[bones[i].first], b = Layout().joints[bones[i].second];
    INFO(a << " - " << b);
    const double s = BoneLengths::StatureShare(a, b);
    if (s == 0.0) continue;
    REQUIRE(lengths.lengths()[i].has_value());
    if (a.find("wrist") != std::string::npos || b.find("wrist") != std::string::npos) {
      // Its own median (0.40 m) is 50 % off the body's proportions; its spread makes it weigh
      // little: the combination lies within 10 % of the share of the stature.
      CHECK(std::abs(*lengths.lengths()[i] / (stature * s) - 1.0) < 0.10);
      CHECK(lengths.uncertainties()[i] < BoneLengths::kShareSpread * stature * s);
    } else {
      // Well measured: its own length, which the prior barely moves.
      CHECK(*lengths.lengths()[i] == Approx(stature * s).epsilon(0.01));
    }
  }
}

TEST_CASE("fit: a joint triangulated far off along one view's ray goes back where its bones put it",
          "[unit]") {
  const std::vector<Vec3> truth = Person();
  const std::vector<Mat34> cameras = {Camera(0.0), Camera(2.0), Camera(4.0)};
  std::vector<core::PersonView> views;
  for (int c = 0; c < 3; ++c) views.push_back(View(c, cameras[static_cast<std::size_t>(c)], truth));
  const auto& bones = Layout().bones;
  std::vector<std::optional<double>> lengths;
  for (const auto& b : bones) {
    lengths.push_back(
        (truth[static_cast<std::size_t>(b.first)] - truth[static_cast<std::size_t>(b.second)])
            .norm());
  }
  // The right wrist (6) starts 1.2 m away from the truth along camera 0's ray through it (a
  // two-view triangulation of nearly parallel rays): camera 0's keypoint still fits the start,
  // the other views' keypoints are too far from it to be used. The fit puts it on camera 0's
  // ray at the forearm's length from the elbow (of the ray's two points at that distance, the
  // one on the start's side).
  const Vec3 centre = -cameras[0].leftCols<3>().inverse() * cameras[0].col(3);
  std::vector<std::optional<Vec3>> start(truth.begin(), truth.end());
  start[6] = truth[6] + 1.2 * (truth[6] - centre).normalized();
  const std::vector<std::optional<Vec3>> fitted =
      FitJoints(start, views, cameras, bones, lengths, nullptr, FitOptions{});
  REQUIRE(fitted[6].has_value());
  const Vec2 seen = (cameras[0] * fitted[6]->homogeneous()).hnormalized();
  CHECK((seen - views[0].observation.points_px[6]).norm() <
        FitOptions{}.reprojection_sigma * views[0].observation.scale_px);
  CHECK((*fitted[6] - truth[6]).norm() < 0.15);
  for (std::size_t i = 0; i < bones.size(); ++i) {
    CHECK(Length(fitted, bones[i]) == Approx(*lengths[i]).margin(0.01));
  }
  // The other joints stay where their views put them.
  for (std::size_t k = 0; k < truth.size(); ++k) {
    if (k != 6) CHECK((*fitted[k] - truth[k]).norm() < 0.02);
  }
}

TEST_CASE("fit: joints move towards where three views see them, bones keep the track's lengths",
          "[unit]") {
  const std::vector<Vec3> truth = Person();
  const std::vector<Mat34> cameras = {Camera(0.0), Camera(2.0), Camera(4.0)};
  std::vector<core::PersonView> views;
  for (int c = 0; c < 3; ++c) views.push_back(View(c, cameras[static_cast<std::size_t>(c)], truth));
  // One view's right wrist is on somebody else (200 px off): the robust loss ignores it.
  views[1].observation.points_px[6] += Vec2(200, -150);
  // The start: the truth with 2 cm of noise (a triangulation); the head top missing.
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.02);
  std::vector<std::optional<Vec3>> start(truth.size());
  for (std::size_t k = 0; k + 1 < truth.size(); ++k) {
    start[k] = truth[k] + Vec3(noise(rng), noise(rng), noise(rng));
  }
  const auto& bones = Layout().bones;
  std::vector<std::optional<double>> lengths;
  for (const auto& b : bones) {
    lengths.push_back(
        (truth[static_cast<std::size_t>(b.first)] - truth[static_cast<std::size_t>(b.second)])
            .norm());
  }
  const std::vector<std::optional<Vec3>> fitted =
      FitJoints(start, views, cameras, bones, lengths, nullptr, FitOptions{});
  REQUIRE(fitted.size() == truth.size());
  CHECK_FALSE(fitted[13].has_value());  // no start: stays missing
  double before = 0.0, after = 0.0;
  for (std::size_t k = 0; k + 1 < truth.size(); ++k) {
    REQUIRE(fitted[k].has_value());
    before += (*start[k] - truth[k]).norm();
    after += (*fitted[k] - truth[k]).norm();
    CHECK((*fitted[k] - truth[k]).norm() < 0.03);
  }
  CHECK(after < 0.8 * before);  // a correction towards the views, not a new triangulation
  for (std::size_t i = 0; i < bones.size(); ++i) {
    if (bones[i].second == 13) continue;  // the head's top is missing
    CHECK(Length(fitted, bones[i]) == Approx(*lengths[i]).margin(0.003));
  }
  // Without any view the start is kept as it is.
  CHECK(FitJoints(start, {}, cameras, bones, lengths, nullptr, FitOptions{}) == start);
}

}  // namespace mvtrack::body
