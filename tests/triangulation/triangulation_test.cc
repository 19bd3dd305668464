#include "triangulation/triangulation.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "geometry/triangulation.h"
#include "support/eigen_matchers.h"
#include "triangulation/synthetic_person.h"

namespace mvtrack::triangulation {
namespace {

using testing::FrameRange;
using testing::IsApproxVec;
using testing::kNumJoints;
using testing::MakeTracklet;
using testing::ViewSpec;
using testing::Walker;

constexpr TriangulationMethod kAllMethods[] = {
    TriangulationMethod::kCmmt, TriangulationMethod::kDlt, TriangulationMethod::kRansac};

TriangulationOptions WithMethod(TriangulationMethod method) {
  TriangulationOptions options;
  options.method = method;
  return options;
}

/// Error of a 3D tracklet against the walker's ground truth over `frames`.
struct ErrorSummary {
  double mean_m = 0.0;
  double max_m = 0.0;
  int count = 0;    ///< triangulated (frame, point) slots
  int missing = 0;  ///< slots without a point
};

ErrorSummary Evaluate(const core::Tracklet3D& out,
                      const Walker& walker,
                      const std::vector<FrameIndex>& frames,
                      bool box_mode) {
  ErrorSummary s;
  for (const FrameIndex t : frames) {
    const std::vector<Vec3> truth =
        box_mode ? std::vector<Vec3>{walker.Pelvis(t)} : walker.Joints(t);
    const int f = out.IndexOf(t);
    for (std::size_t k = 0; k < truth.size(); ++k) {
      if (f < 0 || !out.points[static_cast<std::size_t>(f)][k].has_value()) {
        ++s.missing;
        continue;
      }
      const double e = (*out.points[static_cast<std::size_t>(f)][k] - truth[k]).norm();
      s.mean_m += e;
      s.max_m = std::max(s.max_m, e);
      ++s.count;
    }
  }
  if (s.count > 0) s.mean_m /= s.count;
  return s;
}

/// Tracklets of `walker` in every camera of `cameras` over frames [0, last], one per camera.
std::vector<core::Tracklet2D> AllViews(const std::vector<geometry::CameraModel>& cameras,
                                       const Walker& walker,
                                       FrameIndex last,
                                       const ViewSpec& spec,
                                       std::mt19937* rng) {
  std::vector<core::Tracklet2D> tracklets;
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    tracklets.push_back(MakeTracklet(
        cameras[c], static_cast<TrackId2D>(c + 1), walker, FrameRange(0, last), spec, rng));
  }
  return tracklets;
}

TEST_CASE("TriangulationOptions validation and method names", "[unit]") {
  std::string why;
  CHECK(TriangulationOptions{}.Validate(&why));
  auto invalid = [](auto mutate) {
    TriangulationOptions o;
    mutate(o);
    std::string reason;
    const bool ok = o.Validate(&reason);
    return !ok && !reason.empty();
  };
  CHECK(invalid([](TriangulationOptions& o) { o.phi = -1; }));
  CHECK(invalid([](TriangulationOptions& o) { o.kappa_m = 0.0; }));
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(invalid([&](TriangulationOptions& o) { o.kappa_m = inf; }));
  CHECK(invalid([](TriangulationOptions& o) { o.min_confidence = 1.5; }));
  CHECK(invalid([&](TriangulationOptions& o) { o.min_confidence = nan; }));
  CHECK(invalid([](TriangulationOptions& o) { o.ransac_threshold_px = -2.0; }));
  CHECK(invalid([](TriangulationOptions& o) { o.min_inliers = 0; }));
  CHECK(invalid([](TriangulationOptions& o) { o.max_views = 1; }));
  CHECK(invalid([](TriangulationOptions& o) { o.max_views = -3; }));
  CHECK(invalid([](TriangulationOptions& o) { o.method = static_cast<TriangulationMethod>(7); }));
  TriangulationOptions no_interp;
  no_interp.phi = 0;
  CHECK(no_interp.Validate(nullptr));

  for (const TriangulationMethod m : kAllMethods) {
    CHECK(TriangulationMethodFromName(TriangulationMethodName(m)) == m);
  }
  CHECK(TriangulationMethodName(TriangulationMethod::kCmmt) == "cmmt");
  CHECK_FALSE(TriangulationMethodFromName("svd").has_value());
}

TEST_CASE("Clean 2D: every method recovers the truth to < 1 cm", "[unit]") {
  const auto cameras = testing::RoomCameras();
  const auto rig = testing::MakeRig(cameras);
  const Walker walker;
  for (const bool box_mode : {false, true}) {
    std::mt19937 rng(1);
    const auto tracklets = AllViews(cameras, walker, 9, ViewSpec{box_mode, 0.0}, &rng);
    const std::vector<int> cluster = {2, 0, 3, 1};
    const int num_points = box_mode ? 1 : kNumJoints;
    for (const TriangulationMethod m : kAllMethods) {
      CAPTURE(box_mode, TriangulationMethodName(m));
      const core::Tracklet3D out =
          TriangulatePerson(rig, tracklets, cluster, 0, 10, num_points, WithMethod(m));
      CHECK(out.frames == FrameRange(0, 9));
      CHECK(out.cameras == std::vector<CameraId>{3, 5, 8, 13});
      CHECK(out.source_tracklets == cluster);
      for (const auto& row : out.points) CHECK(static_cast<int>(row.size()) == num_points);
      const ErrorSummary e = Evaluate(out, walker, FrameRange(0, 9), box_mode);
      CHECK(e.missing == 0);
      CHECK(e.max_m < 0.01);
    }
  }
}

TEST_CASE("One corrupted view: CMMT and RANSAC stay accurate while DLT degrades", "[unit]") {
  const auto cameras = testing::RoomCameras();
  const auto rig = testing::MakeRig(cameras);
  const Walker walker;
  Walker other;  // the wrong person seen by camera index 2 during frames 3..7
  other.start = Vec3(1.0, 1.5, 0.0);
  other.velocity_mps = Vec3(-0.8, -0.3, 0.0);
  const std::vector<FrameIndex> corrupted = {3, 4, 5, 6, 7, 10, 11};

  std::mt19937 rng(2024);
  const ViewSpec spec{false, 1.0};
  std::vector<core::Tracklet2D> tracklets;
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    tracklets.push_back(MakeTracklet(cameras[c],
                                     static_cast<TrackId2D>(c + 1),
                                     walker,
                                     FrameRange(0, 13),
                                     spec,
                                     &rng,
                                     [&](FrameIndex t, core::Observation2D* obs) {
                                       if (c == 2 && t >= 3 && t <= 7) {
                                         // Association failure: another person's joints (the
                                         // paper's main outlier source).
                                         const auto body = other.Joints(t);
                                         *obs = testing::Observe(cameras[c], body, body, 1.0, &rng);
                                       }
                                       if (c == 1 && (t == 10 || t == 11)) {
                                         // Gross 2D estimation error: every joint shifted by (120,
                                         // -80) px.
                                         for (Vec2& x : obs->points_px) x += Vec2(120.0, -80.0);
                                       }
                                     }));
  }
  const std::vector<int> cluster = {0, 1, 2, 3};
  ErrorSummary on_corrupted[3], overall[3];
  for (std::size_t i = 0; i < 3; ++i) {
    const core::Tracklet3D out =
        TriangulatePerson(rig, tracklets, cluster, 0, 14, kNumJoints, WithMethod(kAllMethods[i]));
    on_corrupted[i] = Evaluate(out, walker, corrupted, false);
    overall[i] = Evaluate(out, walker, FrameRange(0, 13), false);
  }
  const ErrorSummary& cmmt = on_corrupted[0];
  const ErrorSummary& dlt = on_corrupted[1];
  const ErrorSummary& ransac = on_corrupted[2];
  // Measured (seed 2024, 1 px noise) mean errors on the corrupted frames are reported in
  // docs/DECISIONS.md; the assertions only encode the ordering with wide margins.
  CAPTURE(cmmt.mean_m, dlt.mean_m, ransac.mean_m, cmmt.max_m, dlt.max_m, ransac.max_m);
  CAPTURE(overall[0].mean_m, overall[1].mean_m, overall[2].mean_m);
  CHECK(cmmt.missing == 0);
  CHECK(ransac.missing == 0);
  CHECK(dlt.missing == 0);
  CHECK(cmmt.mean_m < 0.02);
  CHECK(ransac.mean_m < 0.02);
  CHECK(dlt.mean_m > 0.1);
  CHECK(cmmt.mean_m * 5.0 < dlt.mean_m);
  CHECK(ransac.mean_m * 5.0 < dlt.mean_m);
  CHECK(overall[0].mean_m < overall[1].mean_m);
  CHECK(overall[2].mean_m < overall[1].mean_m);
}

TEST_CASE("Two of six views corrupted (box mode): CMMT and RANSAC stay accurate, DLT degrades",
          "[unit]") {
  const auto cameras = testing::RingOfCameras(6, 3.5, 2.6, Vec3(0.0, 0.0, 1.0), 1000.0, 1920, 1080);
  const auto rig = testing::MakeRig(cameras);
  const Walker walker;
  std::mt19937 rng(77);
  std::vector<core::Tracklet2D> tracklets;
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    tracklets.push_back(MakeTracklet(cameras[c],
                                     static_cast<TrackId2D>(c),
                                     walker,
                                     FrameRange(0, 19),
                                     ViewSpec{true, 0.5},
                                     &rng,
                                     [&](FrameIndex t, core::Observation2D* obs) {
                                       if (t % 2 != 0) return;
                                       if (c == 1)
                                         for (Vec2& x : obs->points_px) x += Vec2(90.0, 40.0);
                                       if (c == 4)
                                         for (Vec2& x : obs->points_px) x += Vec2(-60.0, 110.0);
                                     }));
  }
  const std::vector<int> cluster = {0, 1, 2, 3, 4, 5};
  std::vector<FrameIndex> even;
  for (FrameIndex t = 0; t < 20; t += 2) even.push_back(t);
  ErrorSummary e[3];
  for (std::size_t i = 0; i < 3; ++i) {
    const auto out =
        TriangulatePerson(rig, tracklets, cluster, 0, 20, 1, WithMethod(kAllMethods[i]));
    e[i] = Evaluate(out, walker, even, true);
  }
  CAPTURE(e[0].mean_m, e[1].mean_m, e[2].mean_m);
  CHECK(e[0].missing == 0);
  CHECK(e[2].missing == 0);
  CHECK(e[0].mean_m < 0.02);
  CHECK(e[2].mean_m < 0.02);
  CHECK(e[1].mean_m > 0.1);
}

TEST_CASE("Missing observations: CMMT fills frames where DLT has fewer than two views", "[unit]") {
  const auto cameras = testing::RoomCameras();
  const auto rig = testing::MakeRig(cameras);
  const Walker walker;
  std::mt19937 rng(5);
  const ViewSpec spec{false, 0.0};
  std::vector<core::Tracklet2D> tracklets;
  tracklets.push_back(MakeTracklet(cameras[0], 1, walker, FrameRange(0, 11), spec, &rng));
  for (std::size_t c = 1; c < 4; ++c) {
    // Cameras 1..3 lose the person at frames 5-6 (camera 0 alone sees them) and one more frame.
    tracklets.push_back(MakeTracklet(cameras[c],
                                     static_cast<TrackId2D>(c + 1),
                                     walker,
                                     FrameRange(0, 11, {5, 6, static_cast<FrameIndex>(7 + c)}),
                                     spec,
                                     &rng));
  }
  const std::vector<int> cluster = {0, 1, 2, 3};
  const std::vector<FrameIndex> gap = {5, 6};

  const auto dlt = TriangulatePerson(
      rig, tracklets, cluster, 0, 12, kNumJoints, WithMethod(TriangulationMethod::kDlt));
  const auto ransac = TriangulatePerson(
      rig, tracklets, cluster, 0, 12, kNumJoints, WithMethod(TriangulationMethod::kRansac));
  TriangulationStats stats;
  PersonTriangulator cmmt_triangulator(WithMethod(TriangulationMethod::kCmmt));
  const auto cmmt =
      cmmt_triangulator.Triangulate(rig, tracklets, cluster, 0, 12, kNumJoints, &stats);
  for (const FrameIndex t : gap) {
    CHECK(dlt.IndexOf(t) < 0);
    CHECK(ransac.IndexOf(t) < 0);
    CHECK(cmmt.IndexOf(t) >= 0);
  }
  CHECK(stats.num_interpolated_2d > 0);
  const ErrorSummary filled = Evaluate(cmmt, walker, gap, false);
  CAPTURE(filled.mean_m, filled.max_m);
  CHECK(filled.missing == 0);
  CHECK(filled.max_m < 0.03);
  // Everywhere else CMMT still covers every frame and stays accurate.
  const ErrorSummary all = Evaluate(cmmt, walker, FrameRange(0, 11), false);
  CHECK(all.missing == 0);
  CHECK(all.max_m < 0.03);
  CHECK(Evaluate(dlt, walker, FrameRange(0, 11), false).missing == 2 * kNumJoints);
}

TEST_CASE("CMMT interpolation follows Eq. 6 and respects the window phi", "[unit]") {
  const auto cameras = testing::RoomCameras();
  const auto rig = testing::MakeRig({cameras[0], cameras[1]});
  const Walker walker;
  std::mt19937 rng(9);
  const ViewSpec box{true, 0.0};
  // Camera A observes frames 0..10, camera B misses frames 4, 5 and 6.
  std::vector<core::Tracklet2D> tracklets = {
      MakeTracklet(cameras[0], 1, walker, FrameRange(0, 10), box, &rng),
      MakeTracklet(cameras[1], 2, walker, FrameRange(0, 10, {4, 5, 6}), box, &rng)};
  const core::Tracklet2D& a = tracklets[0];
  const std::vector<int> cluster = {0, 1};
  const Mat34& pa = rig.projection(0);
  const Mat34& pb = rig.projection(1);
  auto xa = [&](FrameIndex t) {
    return a.observations[static_cast<std::size_t>(a.IndexOf(t))].points_px[0];
  };
  auto xb = [&](FrameIndex t) {
    const core::Tracklet2D& b = tracklets[1];
    return b.observations[static_cast<std::size_t>(b.IndexOf(t))].points_px[0];
  };
  // Expected CMMT point at a frame t where B is missing: candidates (A observed, B interpolated)
  // and (A interpolated from t-1 and t+1, B interpolated); Eq. 7 averages them.
  auto expected_at = [&](FrameIndex t, FrameIndex b0, FrameIndex b1) {
    const double alpha = static_cast<double>(t - b0) / static_cast<double>(b1 - b0);
    const Vec2 b_interp = (1.0 - alpha) * xb(b0) + alpha * xb(b1);
    const Vec2 a_interp = 0.5 * (xa(t - 1) + xa(t + 1));
    const auto c1 = geometry::TriangulateTwoView(pa, xa(t), pb, b_interp);
    const auto c2 = geometry::TriangulateTwoView(pa, a_interp, pb, b_interp);
    REQUIRE(c1.has_value());
    REQUIRE(c2.has_value());
    REQUIRE((*c1 - *c2).norm() <= 0.2);
    return Vec3(0.5 * (*c1 + *c2));
  };
  auto point_at = [](const core::Tracklet3D& out, FrameIndex t) -> std::optional<Vec3> {
    const int f = out.IndexOf(t);
    if (f < 0) return std::nullopt;
    return out.points[static_cast<std::size_t>(f)][0];
  };

  SECTION("phi = 7 fills 4..6 from frames 3 and 7") {
    const auto out = TriangulatePerson(rig, tracklets, cluster, 0, 11, 1, TriangulationOptions{});
    for (const FrameIndex t : {4, 5, 6}) {
      const auto p = point_at(out, t);
      REQUIRE(p.has_value());
      CHECK_THAT(*p, IsApproxVec(expected_at(t, 3, 7), 1e-9));
      CHECK((*p - walker.Pelvis(t)).norm() < 0.01);
    }
  }
  SECTION("an endpoint exactly phi frames away is used, phi + 1 is not") {
    TriangulationOptions options;
    options.phi = 2;  // frame 5: 3 and 7 are 2 away; frames 4 and 6: one endpoint is 3 away
    const auto out = TriangulatePerson(rig, tracklets, cluster, 0, 11, 1, options);
    CHECK_FALSE(point_at(out, 4).has_value());
    CHECK_FALSE(point_at(out, 6).has_value());
    REQUIRE(point_at(out, 5).has_value());
    CHECK_THAT(*point_at(out, 5), IsApproxVec(expected_at(5, 3, 7), 1e-9));
    options.phi = 3;
    const auto wider = TriangulatePerson(rig, tracklets, cluster, 0, 11, 1, options);
    REQUIRE(point_at(wider, 4).has_value());
    CHECK_THAT(*point_at(wider, 4), IsApproxVec(expected_at(4, 3, 7), 1e-9));
  }
  SECTION("phi = 0 disables interpolation, like DLT") {
    TriangulationOptions options;
    options.phi = 0;
    const auto out = TriangulatePerson(rig, tracklets, cluster, 0, 11, 1, options);
    CHECK(out.frames == FrameRange(0, 10, {4, 5, 6}));
  }
  SECTION("the nearest *valid* observation is the endpoint") {
    // B's point at frame 3 has confidence 0: the interpolation at 5 spans frames 2..7.
    core::Tracklet2D& b = tracklets[1];
    b.observations[static_cast<std::size_t>(b.IndexOf(3))].confidence[0] = 0.0;
    const auto out = TriangulatePerson(rig, tracklets, cluster, 0, 11, 1, TriangulationOptions{});
    REQUIRE(point_at(out, 5).has_value());
    CHECK_THAT(*point_at(out, 5), IsApproxVec(expected_at(5, 2, 7), 1e-9));
  }
  SECTION("DLT and RANSAC do not interpolate") {
    for (const TriangulationMethod m : {TriangulationMethod::kDlt, TriangulationMethod::kRansac}) {
      const auto out = TriangulatePerson(rig, tracklets, cluster, 0, 11, 1, WithMethod(m));
      CHECK(out.frames == FrameRange(0, 10, {4, 5, 6}));
    }
  }
}

TEST_CASE("CMMT gaps longer than phi stay empty (box mode)", "[unit]") {
  const auto cameras = testing::RoomCameras();
  const auto rig = testing::MakeRig(cameras);
  const Walker walker;
  std::mt19937 rng(11);
  std::vector<FrameIndex> gap;
  for (FrameIndex t = 15; t <= 31; ++t) gap.push_back(t);
  std::vector<core::Tracklet2D> tracklets;
  const ViewSpec box{true, 0.0};
  tracklets.push_back(MakeTracklet(cameras[0], 1, walker, FrameRange(0, 39), box, &rng));
  for (std::size_t c = 1; c < 4; ++c) {
    tracklets.push_back(MakeTracklet(
        cameras[c], static_cast<TrackId2D>(c + 1), walker, FrameRange(0, 39, gap), box, &rng));
  }
  const std::vector<int> cluster = {0, 1, 2, 3};
  // A 17-frame gap: no frame inside has both endpoints within phi = 7.
  const auto out = TriangulatePerson(rig, tracklets, cluster, 0, 40, 1, TriangulationOptions{});
  for (const FrameIndex t : gap) CHECK(out.IndexOf(t) < 0);
  CHECK(out.frames.size() == 40 - gap.size());

  TriangulationOptions wide;
  wide.phi = 20;
  const auto filled = TriangulatePerson(rig, tracklets, cluster, 0, 40, 1, wide);
  CHECK(filled.frames == FrameRange(0, 39));
  // The pelvis moves linearly, so interpolating across the gap stays close to the truth.
  const ErrorSummary e = Evaluate(filled, walker, gap, true);
  CAPTURE(e.mean_m, e.max_m);
  CHECK(e.missing == 0);
  CHECK(e.max_m < 0.05);
}

TEST_CASE("A single-camera cluster yields no 3D points", "[unit]") {
  const auto cameras = testing::RoomCameras();
  const auto rig = testing::MakeRig(cameras);
  const Walker walker;
  std::mt19937 rng(13);
  // Two fragments of camera 5 (one overlapping the other) and nothing else.
  const std::vector<core::Tracklet2D> tracklets = {
      MakeTracklet(cameras[1], 1, walker, FrameRange(0, 19), ViewSpec{}, &rng),
      MakeTracklet(cameras[1], 2, walker, FrameRange(15, 39), ViewSpec{false, 3.0}, &rng)};
  for (const TriangulationMethod m : kAllMethods) {
    TriangulationStats stats;
    PersonTriangulator triangulator(WithMethod(m));
    const auto out = triangulator.Triangulate(rig, tracklets, {0, 1}, 0, 40, kNumJoints, &stats);
    CHECK(out.frames.empty());
    CHECK(out.points.empty());
    CHECK(out.cameras == std::vector<CameraId>{5});
    CHECK(out.source_tracklets == std::vector<int>{0, 1});
    CHECK(stats.num_pairs_evaluated == 0);
  }
}

TEST_CASE("Same-camera fragments form one view and are never paired", "[unit]") {
  const auto cameras = testing::RoomCameras();
  const auto rig = testing::MakeRig(cameras);
  const Walker walker;
  std::mt19937 rng(17);
  auto shift_and_dim = [](FrameIndex, core::Observation2D* obs) {
    for (Vec2& x : obs->points_px) x += Vec2(150.0, 0.0);
    for (double& c : obs->confidence) c = 0.5;
  };
  // Camera 3 holds a good fragment and an overlapping, wrong, less confident fragment.
  const std::vector<core::Tracklet2D> tracklets = {
      MakeTracklet(cameras[0], 1, walker, FrameRange(0, 9), ViewSpec{}, &rng),
      MakeTracklet(cameras[0], 2, walker, FrameRange(0, 9), ViewSpec{}, &rng, shift_and_dim),
      MakeTracklet(cameras[1], 3, walker, FrameRange(0, 9), ViewSpec{}, &rng),
      MakeTracklet(cameras[2], 4, walker, FrameRange(0, 9), ViewSpec{}, &rng)};
  const std::vector<int> cluster = {0, 1, 2, 3};

  TriangulationOptions cmmt;
  cmmt.phi = 0;  // observed points only: the candidate count is then exact
  TriangulationStats stats;
  PersonTriangulator triangulator(cmmt);
  const auto out = triangulator.Triangulate(rig, tracklets, cluster, 0, 10, kNumJoints, &stats);
  // Per (frame, joint): view 3 has 2 points, views 5 and 8 one each -> 2 + 2 + 1 = 5 pairs; pairing
  // the two camera-3 fragments would make it 6.
  CHECK(stats.num_pairs_evaluated == 5 * 10 * kNumJoints);
  CHECK(out.cameras == std::vector<CameraId>{3, 5, 8});
  const ErrorSummary e = Evaluate(out, walker, FrameRange(0, 9), false);
  CHECK(e.missing == 0);
  CHECK(e.max_m < 0.01);

  // DLT and RANSAC use one point per view: the most confident one.
  for (const TriangulationMethod m : {TriangulationMethod::kDlt, TriangulationMethod::kRansac}) {
    const auto o = TriangulatePerson(rig, tracklets, cluster, 0, 10, kNumJoints, WithMethod(m));
    const ErrorSummary em = Evaluate(o, walker, FrameRange(0, 9), false);
    CHECK(em.missing == 0);
    CHECK(em.max_m < 1e-6);
  }
}

TEST_CASE("Low-confidence points are ignored", "[unit]") {
  const auto cameras = testing::RoomCameras();
  const auto rig = testing::MakeRig(cameras);
  const Walker walker;
  std::mt19937 rng(19);
  std::vector<core::Tracklet2D> tracklets = AllViews(cameras, walker, 9, ViewSpec{}, &rng);
  // Camera 13's joints are garbage but flagged with confidence 0.05 (< min_confidence 0.1);
  // camera 8's right wrist is missing (confidence 0) with a garbage position.
  for (auto& obs : tracklets[3].observations) {
    for (Vec2& x : obs.points_px) x += Vec2(-200.0, 150.0);
    for (double& c : obs.confidence) c = 0.05;
  }
  for (auto& obs : tracklets[2].observations) {
    obs.points_px[6] = Vec2(5.0, 5.0);
    obs.confidence[6] = 0.0;
  }
  const std::vector<int> cluster = {0, 1, 2, 3};
  for (const TriangulationMethod m : kAllMethods) {
    CAPTURE(TriangulationMethodName(m));
    const auto out = TriangulatePerson(rig, tracklets, cluster, 0, 10, kNumJoints, WithMethod(m));
    const ErrorSummary e = Evaluate(out, walker, FrameRange(0, 9), false);
    CHECK(e.missing == 0);
    CHECK(e.max_m < 0.01);
  }
  // Control: with min_confidence 0 the garbage (confidence 0.05, never the confidence-0 wrist) is
  // used. Clean DLT is exact to ~1e-9 m; the garbage moves it by millimetres even though the
  // confidence weight 0.05 damps it.
  TriangulationOptions accept_all = WithMethod(TriangulationMethod::kDlt);
  accept_all.min_confidence = 0.0;
  const ErrorSummary polluted =
      Evaluate(TriangulatePerson(rig, tracklets, cluster, 0, 10, kNumJoints, accept_all),
               walker,
               FrameRange(0, 9),
               false);
  CAPTURE(polluted.max_m);
  CHECK(polluted.missing == 0);
  CHECK(polluted.max_m > 1e-3);
}

TEST_CASE("DLT weights views by confidence", "[unit]") {
  const auto cameras = testing::RoomCameras();
  const auto rig = testing::MakeRig(cameras);
  const Walker walker;
  auto error_with_confidence = [&](double confidence) {
    std::mt19937 rng(23);
    std::vector<core::Tracklet2D> tracklets = AllViews(cameras, walker, 9, ViewSpec{}, &rng);
    for (auto& obs : tracklets[1].observations) {
      for (Vec2& x : obs.points_px) x += Vec2(40.0, 0.0);
      for (double& c : obs.confidence) c = confidence;
    }
    return Evaluate(TriangulatePerson(rig,
                                      tracklets,
                                      {0, 1, 2, 3},
                                      0,
                                      10,
                                      kNumJoints,
                                      WithMethod(TriangulationMethod::kDlt)),
                    walker,
                    FrameRange(0, 9),
                    false)
        .mean_m;
  };
  const double full = error_with_confidence(1.0);
  const double low = error_with_confidence(0.2);
  CAPTURE(full, low);
  CHECK(full > 0.01);
  CHECK(low < 0.5 * full);
}

TEST_CASE("CMMT abstains when candidates disagree without a majority", "[unit]") {
  const auto cameras = testing::RoomCameras();
  const Walker walker;
  std::mt19937 rng(29);
  // Box mode, no interpolation: three views give three candidates, two views give one.
  auto shifted = [](Vec2 delta) {
    return [delta](FrameIndex, core::Observation2D* obs) { obs->points_px[0] += delta; };
  };
  const std::vector<core::Tracklet2D> tracklets = {
      MakeTracklet(cameras[0], 1, walker, FrameRange(0, 4), ViewSpec{true, 0.0}, &rng),
      MakeTracklet(cameras[1],
                   2,
                   walker,
                   FrameRange(0, 4),
                   ViewSpec{true, 0.0},
                   &rng,
                   shifted(Vec2(0.0, 150.0))),
      MakeTracklet(cameras[2],
                   3,
                   walker,
                   FrameRange(0, 4),
                   ViewSpec{true, 0.0},
                   &rng,
                   shifted(Vec2(-150.0, 0.0)))};
  const auto rig = testing::MakeRig({cameras[0], cameras[1], cameras[2]});
  TriangulationOptions options;
  options.phi = 0;
  TriangulationStats stats;
  PersonTriangulator strict(options);
  const auto out = strict.Triangulate(rig, tracklets, {0, 1, 2}, 0, 5, 1, &stats);
  REQUIRE(stats.num_candidates == 3 * 5);  // all three candidates exist (in front of the cameras)
  CHECK(out.frames.empty());               // ... but no two agree within kappa

  options.min_inliers = 1;  // paper-literal: any largest cluster, even a singleton
  CHECK(TriangulatePerson(rig, tracklets, {0, 1, 2}, 0, 5, 1, options).frames == FrameRange(0, 4));

  // With only two views there is a single candidate: nothing to vote against, it is accepted.
  options.min_inliers = 2;
  CHECK(TriangulatePerson(rig, tracklets, {0, 1}, 0, 5, 1, options).frames == FrameRange(0, 4));
}

TEST_CASE("max_views keeps the most confident view and then the widest baselines", "[unit]") {
  // Three corner cameras (A, B, C) and three near-duplicates (E near A, F near C, G near B).
  const Vec3 target(0.0, 0.0, 1.0);
  auto cam = [&](CameraId id, double x, double y) {
    return testing::LookAtCamera(id, Vec3(x, y, 2.6), target, 1000.0, 1920, 1080);
  };
  // Camera ids are chosen so that neither "lowest ids" nor "confidence, then lowest id" would pick
  // the clean views.
  const std::vector<geometry::CameraModel> cameras = {cam(5, 3.0, 3.0),
                                                      cam(6, -3.0, 3.0),
                                                      cam(4, -3.0, -3.0),
                                                      cam(1, 2.6, 3.0),
                                                      cam(2, -3.0, -2.6),
                                                      cam(3, -2.6, 3.0)};
  const auto rig = testing::MakeRig(cameras);
  const Walker walker;
  std::mt19937 rng(41);
  std::vector<core::Tracklet2D> tracklets;
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    tracklets.push_back(MakeTracklet(cameras[c],
                                     static_cast<TrackId2D>(c),
                                     walker,
                                     FrameRange(0, 5),
                                     ViewSpec{true, 0.0},
                                     &rng,
                                     [c](FrameIndex, core::Observation2D* obs) {
                                       obs->confidence[0] = c == 0 ? 1.0 : 0.9;
                                       // The near-duplicates E, F, G (half of the views) are
                                       // corrupted.
                                       if (c >= 3)
                                         obs->points_px[0] +=
                                             Vec2(60.0 * static_cast<double>(c), -50.0);
                                     }));
  }
  const std::vector<int> cluster = {0, 1, 2, 3, 4, 5};
  // Expected choice: A (most confident), then C (farthest from A), then B (min distance 6 m to
  // {A, C} beats G's 5.6 m and E's / F's 0.4 m): only clean views, so the result is exact.
  TriangulationOptions capped;
  capped.phi = 0;
  capped.max_views = 3;
  for (const TriangulationMethod m : {TriangulationMethod::kCmmt, TriangulationMethod::kRansac}) {
    CAPTURE(TriangulationMethodName(m));
    capped.method = m;
    TriangulationStats stats;
    PersonTriangulator triangulator(capped);
    const auto out = triangulator.Triangulate(rig, tracklets, cluster, 0, 6, 1, &stats);
    CHECK(stats.num_points_view_capped == 6);
    CHECK(stats.num_pairs_evaluated == 3 * 6);
    const ErrorSummary e = Evaluate(out, walker, FrameRange(0, 5), true);
    CHECK(e.missing == 0);
    CHECK(e.max_m < 1e-6);
  }
  // Uncapped CMMT evaluates all 15 pairs; DLT ignores the cap and suffers from the bad views.
  TriangulationOptions all_views;
  all_views.phi = 0;
  all_views.max_views = 0;
  TriangulationStats stats;
  PersonTriangulator uncapped(all_views);
  uncapped.Triangulate(rig, tracklets, cluster, 0, 6, 1, &stats);
  CHECK(stats.num_pairs_evaluated == 15 * 6);
  CHECK(stats.num_points_view_capped == 0);
  TriangulationOptions dlt = capped;
  dlt.method = TriangulationMethod::kDlt;
  const auto dlt_out = TriangulatePerson(rig, tracklets, cluster, 0, 6, 1, dlt);
  CHECK(Evaluate(dlt_out, walker, FrameRange(0, 5), true).mean_m > 0.05);
}

TEST_CASE("Output is limited to the window and to cameras the rig knows", "[unit]") {
  auto cameras = testing::RoomCameras();
  const Walker walker;
  std::mt19937 rng(31);
  std::vector<core::Tracklet2D> tracklets = AllViews(cameras, walker, 19, ViewSpec{}, &rng);
  // The rig lacks camera 13: its tracklet is ignored.
  const auto rig = testing::MakeRig({cameras[0], cameras[1], cameras[2]});
  for (const TriangulationMethod m : kAllMethods) {
    const auto out =
        TriangulatePerson(rig, tracklets, {3, 0, 1, 2}, 5, 12, kNumJoints, WithMethod(m));
    CHECK(out.frames == FrameRange(5, 11));
    CHECK(out.cameras == std::vector<CameraId>{3, 5, 8});
    CHECK(out.source_tracklets == std::vector<int>{3, 0, 1, 2});
    CHECK(Evaluate(out, walker, FrameRange(5, 11), false).max_m < 0.01);
  }
  // An empty window or a window outside the tracklets gives nothing.
  const TriangulationOptions defaults;
  CHECK(TriangulatePerson(rig, tracklets, {0, 1, 2}, 10, 10, kNumJoints, defaults).frames.empty());
  CHECK(
      TriangulatePerson(rig, tracklets, {0, 1, 2}, 100, 130, kNumJoints, defaults).frames.empty());
}

TEST_CASE("PersonTriangulator reuse gives identical results", "[unit]") {
  const auto cameras = testing::RoomCameras();
  const auto rig = testing::MakeRig(cameras);
  const Walker walker;
  std::mt19937 rng(37);
  const auto poses = AllViews(cameras, walker, 4, ViewSpec{false, 2.0}, &rng);
  const auto boxes = AllViews(cameras, walker, 9, ViewSpec{true, 2.0}, &rng);
  auto same = [](const core::Tracklet3D& a, const core::Tracklet3D& b) {
    if (a.frames != b.frames || a.points.size() != b.points.size()) return false;
    for (std::size_t f = 0; f < a.points.size(); ++f) {
      if (a.points[f] != b.points[f]) return false;  // exact: same arithmetic, same order
    }
    return true;
  };
  const std::vector<int> cluster = {0, 1, 2, 3};
  const TriangulationOptions defaults;
  const auto fresh_poses = TriangulatePerson(rig, poses, cluster, 0, 5, kNumJoints, defaults);
  const auto fresh_boxes = TriangulatePerson(rig, boxes, cluster, 0, 10, 1, defaults);
  CHECK(fresh_poses.frames.size() == 5);
  CHECK(fresh_boxes.frames.size() == 10);
  PersonTriangulator reused(TriangulationOptions{});
  CHECK(same(reused.Triangulate(rig, boxes, cluster, 0, 10, 1), fresh_boxes));
  CHECK(same(reused.Triangulate(rig, poses, cluster, 0, 5, kNumJoints), fresh_poses));
  CHECK(same(reused.Triangulate(rig, boxes, cluster, 0, 10, 1), fresh_boxes));
}

}  // namespace
}  // namespace mvtrack::triangulation
