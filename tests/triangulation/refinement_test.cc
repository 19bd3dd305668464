// Per-window refinement of 3D tracklets (lib/triangulation/refinement.h): duplicate distance,
// temporal outlier rejection, completion of missing points.

#include "triangulation/refinement.h"

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "triangulation/synthetic_person.h"

namespace mvtrack {
namespace {

using triangulation::RefinementOptions;

// A tracklet over `frames` with `points(t)` per frame.
template <typename F>
core::Tracklet3D MakeTracklet3D(const std::vector<FrameIndex>& frames, F points) {
  core::Tracklet3D t;
  for (const FrameIndex f : frames) {
    t.frames.push_back(f);
    std::vector<std::optional<Vec3>> row;
    for (const Vec3& p : points(f)) row.emplace_back(p);
    t.points.push_back(std::move(row));
  }
  return t;
}

// A rigid, non-planar five-point "head" turning about the vertical axis and walking.
std::vector<Vec3> HeadAt(FrameIndex t) {
  const std::vector<Vec3> local = {Vec3(0.10, 0.0, 0.0),
                                   Vec3(0.07, 0.04, 0.03),
                                   Vec3(0.07, -0.04, 0.03),
                                   Vec3(0.0, 0.08, 0.0),
                                   Vec3(0.0, -0.08, 0.0)};
  const double angle = 0.08 * static_cast<double>(t);  // 4.6 degrees per frame
  const Mat3 r = Eigen::AngleAxisd(angle, Vec3::UnitZ()).toRotationMatrix();
  const Vec3 origin(0.05 * static_cast<double>(t), 0.02 * static_cast<double>(t), 1.6);
  std::vector<Vec3> out;
  for (const Vec3& p : local) out.push_back(origin + r * p);
  return out;
}

std::vector<FrameIndex> Range(FrameIndex first, FrameIndex last) {
  std::vector<FrameIndex> f;
  for (FrameIndex t = first; t <= last; ++t) f.push_back(t);
  return f;
}

TEST_CASE("RefinementOptions: defaults are valid, bad values are named", "[unit][triangulation]") {
  std::string why;
  CHECK(RefinementOptions{}.Validate(&why));
  RefinementOptions o;
  o.merge_distance_m = std::numeric_limits<double>::quiet_NaN();
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("merge_distance_m") != std::string::npos);
  o = {};
  o.min_person_point_fraction = 1.5;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("min_person_point_fraction") != std::string::npos);
  o = {};
  o.outlier_distance_m = 0.0;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("outlier_distance_m") != std::string::npos);
  o = {};
  o.fill_neighbors = 0;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("fill_neighbors") != std::string::npos);
}

TEST_CASE("PointDistance averages common points of common frames", "[unit][triangulation]") {
  // a: frames 0-2, two points; b: frames 1-3, shifted by 0.1 m (point 0) and 0.3 m (point 1),
  // point 1 missing at frame 2 in b. Common pairs: frame 1 (2), frame 2 (1) -> 3 pairs.
  core::Tracklet3D a = MakeTracklet3D(Range(0, 2), [](FrameIndex t) {
    return std::vector<Vec3>{Vec3(static_cast<double>(t), 0, 0), Vec3(0, 0, 1)};
  });
  core::Tracklet3D b = MakeTracklet3D(Range(1, 3), [](FrameIndex t) {
    return std::vector<Vec3>{Vec3(static_cast<double>(t) + 0.1, 0, 0), Vec3(0, 0.3, 1)};
  });
  b.points[1][1].reset();
  std::int64_t pairs = 0;
  CHECK(triangulation::PointDistance(a, b, &pairs) == Approx((0.1 + 0.3 + 0.1) / 3.0));
  CHECK(pairs == 3);
  const core::Tracklet3D later = MakeTracklet3D(Range(5, 6), [](FrameIndex) {
    return std::vector<Vec3>{Vec3::Zero(), Vec3::Zero()};
  });
  CHECK(std::isinf(triangulation::PointDistance(a, later, &pairs)));
  CHECK(pairs == 0);
}

TEST_CASE("RefinementOptions: box merge and height bounds are validated", "[unit][triangulation]") {
  std::string why;
  RefinementOptions o;
  o.box_merge_distance_m = -0.1;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("box_merge_distance_m") != std::string::npos);
  o = {};
  o.box_min_height_m = 2.0;  // not below box_max_height_m (2.0)
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("box_min_height_m") != std::string::npos);
  o = {};
  o.box_max_height_m = std::numeric_limits<double>::infinity();
  CHECK_FALSE(o.Validate(&why));
  o = {};
  o.box_min_height_m = -1.0;
  o.box_max_height_m = 3.0;
  CHECK(o.Validate(&why));
}

TEST_CASE("FootprintDistance is the median ground-plane distance of common frames",
          "[unit][triangulation]") {
  // a: frames 0-5 at (t, 0, 1); b: frames 1-6, 0.2 m beside a in y and 0.5 m higher, except
  // frame 3, where b is triangulated 5 m off. Common frames 1-5: distances 0.2 (x4) and 5.
  core::Tracklet3D a = MakeTracklet3D(Range(0, 5), [](FrameIndex t) {
    return std::vector<Vec3>{Vec3(static_cast<double>(t), 0, 1)};
  });
  core::Tracklet3D b = MakeTracklet3D(Range(1, 6), [](FrameIndex t) {
    const double off = t == 3 ? 5.0 : 0.2;
    return std::vector<Vec3>{Vec3(static_cast<double>(t), off, 1.5)};
  });
  std::int64_t frames = 0;
  CHECK(triangulation::FootprintDistance(a, b, &frames) == Approx(0.2));
  CHECK(frames == 5);
  CHECK(triangulation::FootprintDistance(b, a) == Approx(0.2));
  // The mean (what PointDistance takes, in 3D) is dominated by the far frame.
  CHECK(triangulation::PointDistance(a, b) > 1.0);
  // Even count: the mean of the two middle values (frames 1-4: 0.2, 0.2, 5, 0.2 -> 0.2;
  // frames 2-3 only: 0.2 and 5 -> 2.6).
  core::Tracklet3D b23 = b;
  b23.frames = {2, 3};
  b23.points = {b.points[1], b.points[2]};
  CHECK(triangulation::FootprintDistance(a, b23, &frames) == Approx(2.6));
  CHECK(frames == 2);
  // Missing points are skipped; a frame's footprint is the mean of its present points.
  b23.points[1][0].reset();
  CHECK(triangulation::FootprintDistance(a, b23, &frames) == Approx(0.2));
  CHECK(frames == 1);
  core::Tracklet3D two = MakeTracklet3D(Range(2, 2), [](FrameIndex) {
    return std::vector<Vec3>{Vec3(1.0, 0.0, 0.0), Vec3(3.0, 0.6, 9.0)};  // mean (2, 0.3)
  });
  CHECK(triangulation::FootprintDistance(a, two) == Approx(0.3));
  // No common frame.
  core::Tracklet3D late =
      MakeTracklet3D(Range(10, 12), [](FrameIndex) { return std::vector<Vec3>{Vec3(0, 0, 0)}; });
  CHECK(std::isinf(triangulation::FootprintDistance(a, late, &frames)));
  CHECK(frames == 0);
}

TEST_CASE("RemovePointsOutsideHeights drops implausible points and empty frames",
          "[unit][triangulation]") {
  // Frames 0-4, two points: point 0 at z = t - 1 (-1, 0, 1, 2, 3), point 1 at z = 1 except
  // frame 4 (z = 5). Bounds [-0.5, 2] (inclusive): point 0 goes at frames 0 and 4, point 1 at
  // frame 4, which is then empty and dropped.
  core::Tracklet3D t = MakeTracklet3D(Range(0, 4), [](FrameIndex f) {
    const double z = static_cast<double>(f);
    return std::vector<Vec3>{Vec3(0, 0, z - 1.0), Vec3(1, 0, f == 4 ? 5.0 : 1.0)};
  });
  CHECK(triangulation::RemovePointsOutsideHeights(&t, -0.5, 2.0) == 3);
  REQUIRE(t.frames == std::vector<FrameIndex>{0, 1, 2, 3});
  REQUIRE(t.points.size() == 4);
  CHECK_FALSE(t.points[0][0].has_value());
  CHECK(t.points[0][1]->z() == 1.0);
  CHECK(t.points[1][0]->z() == 0.0);
  CHECK(t.points[3][0]->z() == 2.0);  // on the bound: kept
  // Everything out: the tracklet is empty.
  CHECK(triangulation::RemovePointsOutsideHeights(&t, 10.0, 11.0) == 7);
  CHECK(t.frames.empty());
  CHECK(t.points.empty());
}

TEST_CASE("ReprojectionResidual and InconsistentTracklets find another person's tracklet",
          "[unit][triangulation]") {
  // Person A (its exact pelvis track over frames 0-29) and four box tracklets: A seen by
  // cameras 3, 5 and 8 (0.5 px noise), and B, walking 1.5 m beside A, seen by camera 13.
  const auto cameras = testing::RoomCameras();
  const geometry::CameraRig rig = testing::MakeRig(cameras);
  const testing::Walker a;
  testing::Walker b = a;
  b.start += Vec3(0.0, 1.5, 0.0);
  const auto frames = testing::FrameRange(0, 29);
  core::Tracklet3D person =
      MakeTracklet3D(frames, [&](FrameIndex t) { return std::vector<Vec3>{a.Pelvis(t)}; });
  std::mt19937 rng(8);
  const testing::ViewSpec spec{true, 0.5};
  std::vector<core::Tracklet2D> tracklets;
  for (std::size_t c = 0; c < 3; ++c) {
    tracklets.push_back(testing::MakeTracklet(cameras[c], 1, a, frames, spec, &rng));
  }
  tracklets.push_back(testing::MakeTracklet(cameras[3], 2, b, frames, spec, &rng));
  for (std::size_t i = 0; i < 3; ++i) {
    const std::optional<double> r =
        triangulation::ReprojectionResidual(rig, tracklets[i], person, 0.1);
    REQUIRE(r.has_value());
    CHECK(*r < 0.01);  // 0.5 px noise on a scale of hundreds of pixels
  }
  const std::optional<double> rb =
      triangulation::ReprojectionResidual(rig, tracklets[3], person, 0.1);
  REQUIRE(rb.has_value());
  CHECK(*rb > 0.2);
  const std::vector<int> cluster = {0, 1, 2, 3};
  CHECK(triangulation::InconsistentTracklets(rig, tracklets, cluster, person, 0.2, 0.1) ==
        std::vector<int>{3});
  // A limit above B's residual keeps everyone; 0 disables the test.
  CHECK(triangulation::InconsistentTracklets(rig, tracklets, cluster, person, *rb + 0.01, 0.1)
            .empty());
  CHECK(triangulation::InconsistentTracklets(rig, tracklets, cluster, person, 0.0, 0.1).empty());
  // Points below the confidence limit do not compare; a tracklet without a comparable frame has
  // no residual and is kept.
  core::Tracklet2D unsure = tracklets[3];
  for (core::Observation2D& obs : unsure.observations) obs.confidence[0] = 0.05;
  CHECK_FALSE(triangulation::ReprojectionResidual(rig, unsure, person, 0.1).has_value());
  tracklets.push_back(unsure);
  CHECK(triangulation::InconsistentTracklets(rig, tracklets, {0, 1, 2, 3, 4}, person, 0.2, 0.1) ==
        std::vector<int>{3});
  // The median over frames follows the majority of frames: with A's projections in 14 of 30
  // frames the tracklet is still B (split off), with them in 16 of 30 it is A (kept).
  core::Tracklet2D mostly_b = tracklets[3];
  core::Tracklet2D mostly_a = tracklets[3];
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const Vec2 at_a = *cameras[3].ProjectUndistorted(a.Pelvis(frames[f]));
    if (f < 14) mostly_b.observations[f].points_px[0] = at_a;
    if (f >= 14) mostly_a.observations[f].points_px[0] = at_a;
  }
  CHECK(*triangulation::ReprojectionResidual(rig, mostly_b, person, 0.1) > 0.2);
  CHECK(*triangulation::ReprojectionResidual(rig, mostly_a, person, 0.1) < 0.01);
}

TEST_CASE("ReprojectionResidual forgives a cut box's displacement past the cut edge only",
          "[unit][triangulation]") {
  // A's tracklet in camera 3 with every point moved 40 px: a cut box's centre moves inwards,
  // away from the cut edge. The residual counts the displacement unless the observation says
  // the box is cut on the edge the displacement points away from.
  const auto cameras = testing::RoomCameras();
  const geometry::CameraRig rig = testing::MakeRig(cameras);
  const testing::Walker a;
  const auto frames = testing::FrameRange(0, 29);
  const core::Tracklet3D person =
      MakeTracklet3D(frames, [&](FrameIndex t) { return std::vector<Vec3>{a.Pelvis(t)}; });
  const testing::ViewSpec spec{true, 0.0};
  std::mt19937 rng(3);
  const core::Tracklet2D exact = testing::MakeTracklet(cameras[0], 1, a, frames, spec, &rng);
  const double scale = 400.0;
  const auto moved = [&](const Vec2& by, std::uint8_t cut) {
    core::Tracklet2D t = exact;
    for (core::Observation2D& obs : t.observations) {
      obs.points_px[0] += by;
      obs.scale_px = scale;
      obs.cut_edges = cut;
    }
    return *triangulation::ReprojectionResidual(rig, t, person, 0.1);
  };
  // Moved right (projection - observed points left): forgiven when the box is cut on the left.
  CHECK(moved(Vec2(40.0, 0.0), 0) == Approx(40.0 / scale).epsilon(1e-6));
  CHECK(moved(Vec2(40.0, 0.0), core::kCutLeft) == Approx(0.0).margin(1e-9));
  CHECK(moved(Vec2(40.0, 0.0), core::kCutRight) == Approx(40.0 / scale).epsilon(1e-6));
  CHECK(moved(Vec2(-40.0, 0.0), core::kCutRight) == Approx(0.0).margin(1e-9));
  // Moved down: forgiven for a box cut at the top, not at the bottom; only the cut axis is
  // forgiven.
  CHECK(moved(Vec2(0.0, 40.0), core::kCutTop) == Approx(0.0).margin(1e-9));
  CHECK(moved(Vec2(0.0, 40.0), core::kCutBottom) == Approx(40.0 / scale).epsilon(1e-6));
  CHECK(moved(Vec2(0.0, -40.0), core::kCutBottom) == Approx(0.0).margin(1e-9));
  CHECK(moved(Vec2(30.0, 40.0), core::kCutLeft) == Approx(40.0 / scale).epsilon(1e-6));
  CHECK(moved(Vec2(30.0, 40.0), static_cast<std::uint8_t>(core::kCutLeft | core::kCutTop)) ==
        Approx(0.0).margin(1e-9));
}

TEST_CASE("MaxPointsPerFrame counts the best frame", "[unit][triangulation]") {
  core::Tracklet3D t = MakeTracklet3D(Range(0, 2), [](FrameIndex) {
    return std::vector<Vec3>{Vec3::Zero(), Vec3::Ones(), Vec3::UnitX()};
  });
  t.points[0][0].reset();
  t.points[1][0].reset();
  t.points[1][1].reset();
  CHECK(triangulation::MaxPointsPerFrame(t) == 3);
  t.points[2][2].reset();
  CHECK(triangulation::MaxPointsPerFrame(t) == 2);
  CHECK(triangulation::MaxPointsPerFrame(core::Tracklet3D{}) == 0);
}

TEST_CASE("RejectTemporalOutliers removes spikes and keeps fast straight motion",
          "[unit][triangulation]") {
  // Point 0 moves 0.15 m per frame (3.75 m/s at 25 fps), point 1 stands still; point 0 is
  // replaced by a point 0.5 m off at frame 5 and at frames 8-9 (a two-frame run).
  core::Tracklet3D t = MakeTracklet3D(Range(0, 14), [](FrameIndex f) {
    return std::vector<Vec3>{Vec3(0.15 * static_cast<double>(f), 0, 1), Vec3(0, 1, 1)};
  });
  const Vec3 off(0, 0.5, 0);
  *t.points[5][0] += off;
  *t.points[8][0] += off;
  *t.points[9][0] += off;
  RefinementOptions o;
  o.outlier_half_window = 3;
  o.outlier_distance_m = 0.2;
  CHECK(triangulation::RejectTemporalOutliers(&t, o) == 3);
  for (std::size_t f = 0; f < t.frames.size(); ++f) {
    const bool spike = f == 5 || f == 8 || f == 9;
    CHECK(t.points[f][0].has_value() == !spike);
    CHECK(t.points[f][1].has_value());
  }
  // Disabled: nothing happens.
  core::Tracklet3D u = MakeTracklet3D(
      Range(0, 6), [](FrameIndex f) { return std::vector<Vec3>{Vec3(0, 0, f == 3 ? 5.0 : 0.0)}; });
  o.outlier_half_window = 0;
  CHECK(triangulation::RejectTemporalOutliers(&u, o) == 0);
  o.outlier_half_window = 3;
  CHECK(triangulation::RejectTemporalOutliers(&u, o) == 1);
  CHECK_FALSE(u.points[3][0].has_value());
}

TEST_CASE("SmoothTemporally keeps straight motion, averages noise, respects its limits",
          "[unit][triangulation]") {
  // Point 0 moves 0.15 m per frame along x with alternating +-3 cm noise in y; point 1 moves
  // on an exact straight line; point 2 is missing at frame 4.
  const auto truth = [](FrameIndex f) { return Vec3(0.15 * static_cast<double>(f), 0, 1); };
  core::Tracklet3D t = MakeTracklet3D(Range(0, 20), [&](FrameIndex f) {
    const double noise = (f % 2 == 0 ? 0.03 : -0.03);
    return std::vector<Vec3>{
        truth(f) + Vec3(0, noise, 0), Vec3(0.02 * static_cast<double>(f), 1, 1), Vec3(0, 2, 1)};
  });
  t.points[4][2].reset();
  RefinementOptions o;
  o.smooth_half_window = 5;
  const core::Tracklet3D before = t;
  CHECK(triangulation::SmoothTemporally(&t, o) > 0);
  double error_before = 0.0;
  double error_after = 0.0;
  for (std::size_t f = 0; f < t.frames.size(); ++f) {
    error_before += (*before.points[f][0] - truth(t.frames[f])).norm();
    error_after += (*t.points[f][0] - truth(t.frames[f])).norm();
    // A line is kept exactly, also at the ends, where the fit sees one side only.
    CHECK((*t.points[f][1] - *before.points[f][1]).norm() < 1e-9);
    if (f != 4) CHECK((*t.points[f][2] - *before.points[f][2]).norm() < 1e-9);
  }
  CHECK(error_after < 0.5 * error_before);
  CHECK_FALSE(t.points[4][2].has_value());  // missing stays missing
  // Only points seen by at most smooth_max_views cameras change.
  core::Tracklet3D u = before;
  std::vector<std::vector<int>> views(u.frames.size(), std::vector<int>(3, 3));
  views[7][0] = 2;
  o.smooth_max_views = 2;
  CHECK(triangulation::SmoothTemporally(&u, o, &views) == 1);
  for (std::size_t f = 0; f < u.frames.size(); ++f) {
    CHECK((*u.points[f][0] == *before.points[f][0]) == (f != 7));
  }
  // Disabled, or too few samples within the half window: nothing changes.
  core::Tracklet3D w = before;
  o.smooth_half_window = 0;
  CHECK(triangulation::SmoothTemporally(&w, o) == 0);
  core::Tracklet3D sparse = MakeTracklet3D({0, 10, 20}, [](FrameIndex f) {
    return std::vector<Vec3>{Vec3(0, static_cast<double>(f % 3), 0)};
  });
  o.smooth_half_window = 5;
  CHECK(triangulation::SmoothTemporally(&sparse, o) == 0);
  o.smooth_half_window = -1;
  std::string why;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("smooth_half_window") != std::string::npos);
  o.smooth_half_window = 5;
  o.smooth_max_views = -1;
  CHECK_FALSE(o.Validate(&why));
  CHECK(why.find("smooth_max_views") != std::string::npos);
}

TEST_CASE("ObservingViews counts the cameras that saw each point", "[unit][triangulation]") {
  // Camera 0 has two tracklets (fragments: frames 0-1 and 2-3), camera 1 one (frames 1-2).
  const auto tracklet =
      [](CameraId camera, std::vector<FrameIndex> frames, std::vector<double> confidence) {
        core::Tracklet2D t;
        t.camera_id = camera;
        for (const FrameIndex f : frames) {
          t.frames.push_back(f);
          core::Observation2D obs;
          obs.points_px = {Vec2(1, 1), Vec2(2, 2)};
          obs.confidence = confidence;
          t.observations.push_back(obs);
        }
        return t;
      };
  const std::vector<core::Tracklet2D> tracklets = {tracklet(0, {0, 1}, {1.0, 0.05}),
                                                   tracklet(0, {2, 3}, {1.0, 1.0}),
                                                   tracklet(1, {1, 2}, {0.9, 0.0}),
                                                   tracklet(2, {0, 1, 2, 3}, {1.0, 1.0})};
  const core::Tracklet3D person = MakeTracklet3D(Range(0, 3), [](FrameIndex) {
    return std::vector<Vec3>{Vec3::Zero(), Vec3::Zero()};
  });
  // Tracklet 3 (camera 2) is not in the cluster.
  const auto views = triangulation::ObservingViews(tracklets, {0, 1, 2}, person, 0.1);
  REQUIRE(views.size() == 4);
  CHECK(views[0] == std::vector<int>{1, 0});  // camera 0; point 1 below min_confidence
  CHECK(views[1] == std::vector<int>{2, 0});  // cameras 0 and 1; camera 1's point 1 missing
  CHECK(views[2] == std::vector<int>{2, 1});
  CHECK(views[3] == std::vector<int>{1, 1});
}

TEST_CASE("CompleteMissingPoints carries a point rigidly with its neighbours",
          "[unit][triangulation]") {
  core::Tracklet3D t = MakeTracklet3D(Range(10, 25), HeadAt);
  // Point 4 (one "ear") is missing on frames 13-17 (two references: 12 and 18) and on
  // 23-25 (one reference: 22, the tracklet ends).
  for (const FrameIndex f : {13, 14, 15, 16, 17, 23, 24, 25}) {
    t.points[static_cast<std::size_t>(f - 10)][4].reset();
  }
  RefinementOptions o;
  o.max_fill_gap = 15;
  o.fill_neighbors = 4;
  o.min_points_to_fill = 4;
  const triangulation::CompletionStats stats = triangulation::CompleteMissingPoints(&t, o);
  CHECK(stats.filled == 8);
  CHECK(stats.filled_rigid == 8);
  for (const FrameIndex f : {13, 14, 15, 16, 17, 23, 24, 25}) {
    const auto& p = t.points[static_cast<std::size_t>(f - 10)][4];
    REQUIRE(p.has_value());
    CHECK((*p - HeadAt(f)[4]).norm() < 1e-9);  // a rigid motion is carried exactly
  }
}

TEST_CASE("CompleteMissingPoints: translation with few neighbours, limits respected",
          "[unit][triangulation]") {
  // Two points moving apart: point 0 static, point 1 drifting; point 2 moves with point 0.
  core::Tracklet3D t = MakeTracklet3D(Range(0, 9), [](FrameIndex f) {
    const double s = static_cast<double>(f);
    return std::vector<Vec3>{Vec3(s, 0, 0), Vec3(s, 0.1 * s, 0), Vec3(s, 0, 1)};
  });
  t.points[4][2].reset();
  RefinementOptions o;
  o.fill_neighbors = 1;  // nearest neighbour of point 2 at frame 3 and 5 is point 0
  o.min_points_to_fill = 2;
  o.max_fill_gap = 1;
  auto stats = triangulation::CompleteMissingPoints(&t, o);
  CHECK(stats.filled == 1);
  CHECK(stats.filled_rigid == 0);
  REQUIRE(t.points[4][2].has_value());
  CHECK((*t.points[4][2] - Vec3(4, 0, 1)).norm() < 1e-12);

  // Point 2 missing on frames 2-6, triangulated on 1 and 7. With max_fill_gap = 2, frames 2-3
  // reach frame 1 and frames 5-6 reach frame 7, but frame 4 is 3 frames from both: it stays
  // missing (its filled neighbours never serve as references).
  core::Tracklet3D u = MakeTracklet3D(Range(0, 9), [](FrameIndex f) {
    const double s = static_cast<double>(f);
    return std::vector<Vec3>{Vec3(s, 0, 0), Vec3(s, 1, 0), Vec3(s, 0, 1)};
  });
  for (std::size_t f = 2; f <= 6; ++f) u.points[f][2].reset();
  o.max_fill_gap = 2;
  stats = triangulation::CompleteMissingPoints(&u, o);
  CHECK(stats.filled == 4);
  CHECK_FALSE(u.points[4][2].has_value());
  CHECK(u.points[3][2].has_value());
  CHECK(u.points[5][2].has_value());

  // A frame with too few triangulated points is not completed.
  core::Tracklet3D w = MakeTracklet3D(Range(0, 2), [](FrameIndex f) {
    const double s = static_cast<double>(f);
    return std::vector<Vec3>{Vec3(s, 0, 0), Vec3(s, 1, 0), Vec3(s, 0, 1)};
  });
  w.points[1][1].reset();
  w.points[1][2].reset();
  o.min_points_to_fill = 2;
  CHECK(triangulation::CompleteMissingPoints(&w, o).filled == 0);
  o.min_points_to_fill = 1;
  CHECK(triangulation::CompleteMissingPoints(&w, o).filled == 2);
}

}  // namespace
}  // namespace mvtrack
